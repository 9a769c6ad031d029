// SPDX-License-Identifier: Apache-2.0
#include "core/subproblems.h"

#include "core/block_extents.h"
#include "core/disjoint_sets.h"

namespace ispq {

Subproblems::Subproblems(const TMesh& mesh, const ConsistencyMatrix& consistency,
                         const ArcBundles& bundles) {
  DisjointSets sets(bundles.num_bundles());
  auto join_all = [&](std::span<const LinearTerm> bundle_terms) {
    for (size_t i = 1; i < bundle_terms.size(); ++i)
      sets.Join(bundle_terms[0].var, bundle_terms[i].var);
  };
  for (int r = 0; r < consistency.num_rows(); ++r) {
    join_all(bundles.ToBundleTerms(consistency.row(r)));
  }
  std::vector<LinearTerm> extent;
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int axis = 0; axis < 3; ++axis) {
      extent.clear();
      for (ArcId a : ExtentRowArcs(mesh, b, axis)) extent.push_back({a, 1});
      join_all(bundles.ToBundleTerms(extent));
    }
  }
  subproblem_of_.assign(bundles.num_bundles(), -1);
  std::vector<int32_t> index_of_root(bundles.num_bundles(), -1);
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    const int32_t root = sets.Find(b);
    if (index_of_root[root] < 0) {
      index_of_root[root] = static_cast<int32_t>(bundles_of_.size());
      bundles_of_.emplace_back();
    }
    subproblem_of_[b] = index_of_root[root];
    bundles_of_[index_of_root[root]].push_back(b);
  }
}

}  // namespace ispq
