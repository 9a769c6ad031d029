// SPDX-License-Identifier: Apache-2.0
#include "core/arc_bundles.h"

#include <algorithm>

#include "core/disjoint_sets.h"
#include "core/linear_terms.h"

namespace ispq {

ArcBundles::ArcBundles(const TMesh& mesh, const ConsistencyMatrix& consistency) {
  const int n = mesh.num_arcs();
  DisjointSets sets(n);
  for (int r = 0; r < consistency.num_rows(); ++r) {
    const std::span<const LinearTerm> row = consistency.row(r);
    if (row.size() != 2) continue;  // one arc on each side
    sets.Join(row[0].var, row[1].var);
  }
  // Number bundles in order of their smallest arc.
  bundle_of_arc_.assign(n, kNoId);
  std::vector<std::vector<ArcId>> members;
  for (ArcId a = 0; a < n; ++a) {
    const int32_t root = sets.Find(a);  // the smallest arc of its bundle
    if (root == a) {
      bundle_of_arc_[a] = static_cast<BundleId>(members.size());
      members.emplace_back();
    } else {
      bundle_of_arc_[a] = bundle_of_arc_[root];
    }
    members[bundle_of_arc_[a]].push_back(a);
  }
  for (const auto& list : members) arcs_.Append(list);
}

std::vector<int64_t> ArcBundles::ArcValues(std::span<const int64_t> bundle_values) const {
  std::vector<int64_t> q(bundle_of_arc_.size());
  for (size_t a = 0; a < q.size(); ++a) q[a] = bundle_values[bundle_of_arc_[a]];
  return q;
}

std::vector<LinearTerm> ArcBundles::ToBundleTerms(std::span<const LinearTerm> arc_terms) const {
  std::vector<LinearTerm> terms;
  terms.reserve(arc_terms.size());
  for (const LinearTerm& t : arc_terms) terms.push_back({bundle_of_arc_[t.var], t.coef});
  MergeRepeatedTerms(terms);
  std::sort(terms.begin(), terms.end(),
            [](const LinearTerm& x, const LinearTerm& y) { return x.var < y.var; });
  return terms;
}

std::vector<LinearTerm> ArcBundles::ToArcTerms(std::span<const LinearTerm> bundle_terms) const {
  std::vector<LinearTerm> terms;
  terms.reserve(bundle_terms.size());
  for (const LinearTerm& t : bundle_terms) terms.push_back({arcs_[t.var][0], t.coef});
  return terms;
}

}  // namespace ispq
