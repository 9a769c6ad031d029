// SPDX-License-Identifier: Apache-2.0
#include "core/isp/subproblem_set.h"

#include <algorithm>
#include <unordered_map>
#include <utility>

#include "core/disjoint_sets.h"

namespace ispq {
namespace {

uint64_t HashTerms(std::span<const LinearTerm> terms) {
  uint64_t h = 1469598103934665603ull;
  for (const LinearTerm& t : terms) {
    h = (h ^ static_cast<uint32_t>(t.var)) * 1099511628211ull;
    h = (h ^ static_cast<uint32_t>(t.coef)) * 1099511628211ull;
  }
  return h;
}

bool SameTerms(std::span<const LinearTerm> x, std::span<const LinearTerm> y) {
  return std::equal(
      x.begin(), x.end(), y.begin(), y.end(),
      [](const LinearTerm& a, const LinearTerm& b) { return a.var == b.var && a.coef == b.coef; });
}

}  // namespace

SubproblemSet::SubproblemSet(const ConsistencyMatrix& consistency, const ArcBundles& bundles,
                             const Subproblems& initial, const BundleQuantization& quantization,
                             const InequalityRows& rows, std::vector<uint8_t> floors, int num_arcs,
                             SheetLpFactory new_lp, bool decompose)
    : rows_(rows) {
  context_.quantization = &quantization;
  context_.rows = &rows;
  context_.equalities = &equalities_;
  context_.num_arcs = static_cast<double>(num_arcs);
  context_.new_lp = std::move(new_lp);
  context_.local_index_of_bundle.assign(bundles.num_bundles(), kNoId);
  context_.has_floor = std::move(floors);
  BuildEqualities(consistency, bundles, initial);
  Build(initial, decompose);
}

void SubproblemSet::BuildEqualities(const ConsistencyMatrix& consistency, const ArcBundles& bundles,
                                    const Subproblems& initial) {
  // Rows that bundling made trivial are dropped (paper section 4.4); rows that became identical up
  // to sign are kept once.
  std::unordered_map<uint64_t, std::vector<int32_t>> by_hash;
  std::vector<LinearTerm> terms;
  for (int r = 0; r < consistency.num_rows(); ++r) {
    terms = bundles.ToBundleTerms(consistency.row(r));
    if (terms.empty()) continue;
    if (terms[0].coef < 0) {
      for (LinearTerm& t : terms) t.coef = -t.coef;
    }
    std::vector<int32_t>& same = by_hash[HashTerms(terms)];
    if (std::any_of(same.begin(), same.end(),
                    [&](int32_t e) { return SameTerms(terms, equalities_[e]); })) {
      continue;
    }
    same.push_back(equalities_.size());
    equalities_.Append(terms);
    equality_initial_subproblem_.push_back(initial.subproblem_of(terms[0].var));
  }
}

void SubproblemSet::Build(const Subproblems& initial, bool decompose) {
  const int count = decompose ? initial.num_subproblems() : 1;
  auto subproblem_of_initial = [&](int32_t c) { return decompose ? c : 0; };
  std::vector<std::vector<BundleId>> bundles(count);
  std::vector<std::vector<int32_t>> equalities(count), rows(count);
  const int num_bundles = static_cast<int>(context_.local_index_of_bundle.size());
  for (BundleId b = 0; b < num_bundles; ++b) {
    bundles[subproblem_of_initial(initial.subproblem_of(b))].push_back(b);
  }
  for (int32_t e = 0; e < equalities_.size(); ++e) {
    equalities[subproblem_of_initial(equality_initial_subproblem_[e])].push_back(e);
  }
  for (int32_t r = 0; r < rows_.size(); ++r) {
    rows[subproblem_of_initial(initial.subproblem_of(rows_.terms(r)[0].var))].push_back(r);
  }
  context_.lp_row_of_row.assign(rows_.size(), kNoId);
  subproblem_of_bundle_.assign(num_bundles, kNoId);
  for (int s = 0; s < count; ++s) {
    for (BundleId b : bundles[s]) subproblem_of_bundle_[b] = s;
    subproblems_.push_back(std::make_unique<SheetSubproblem>(
        &context_, std::move(bundles[s]), std::move(equalities[s]), std::move(rows[s])));
  }
}

std::vector<int32_t> SubproblemSet::WithViolatedRows() const {
  std::vector<int32_t> ids;
  for (int32_t r = 0; r < rows_.size(); ++r) {
    if (rows_.active(r) && rows_.violated(r)) {
      ids.push_back(subproblem_of_bundle_[rows_.terms(r)[0].var]);
    }
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

std::vector<int32_t> SubproblemSet::Ids() const {
  std::vector<int32_t> ids;
  for (int32_t id = 0; id < static_cast<int32_t>(subproblems_.size()); ++id) {
    if (subproblems_[id] != nullptr) ids.push_back(id);
  }
  return ids;
}

int SubproblemSet::count() const {
  return static_cast<int>(std::count_if(subproblems_.begin(), subproblems_.end(),
                                        [](const auto& s) { return s != nullptr; }));
}

bool SubproblemSet::MarkRowChanged(int32_t r) {
  if (static_cast<size_t>(r) >= context_.lp_row_of_row.size() ||
      context_.lp_row_of_row[r] == kNoId) {
    return false;
  }
  Of(rows_.terms(r)[0].var).MarkRowChanged(r);
  return true;
}

void SubproblemSet::Attach(std::span<const int32_t> new_rows) {
  if (new_rows.empty()) return;
  context_.lp_row_of_row.resize(rows_.size(), kNoId);
  const int32_t count = static_cast<int32_t>(subproblems_.size());
  DisjointSets sets(count);
  for (int32_t r : new_rows) {
    const std::span<const LinearTerm> terms = rows_.terms(r);
    for (const LinearTerm& t : terms) {
      sets.Join(subproblem_of_bundle_[terms[0].var], subproblem_of_bundle_[t.var]);
    }
  }
  std::vector<std::vector<int32_t>> rows_by_root(count), members(count);
  for (int32_t r : new_rows) {
    rows_by_root[sets.Find(subproblem_of_bundle_[rows_.terms(r)[0].var])].push_back(r);
  }
  for (int32_t s = 0; s < count; ++s) {
    if (subproblems_[s] != nullptr) members[sets.Find(s)].push_back(s);
  }
  for (int32_t root = 0; root < count; ++root) {
    if (rows_by_root[root].empty()) continue;
    if (members[root].size() == 1) {
      subproblems_[root]->AddRows(rows_by_root[root]);
    } else {
      Merge(members[root], rows_by_root[root]);
    }
  }
}

void SubproblemSet::AttachTo(int32_t id, std::span<const int32_t> new_rows) {
  context_.lp_row_of_row.resize(rows_.size(), kNoId);
  subproblems_[id]->AddRows(new_rows);
}

void SubproblemSet::Merge(std::span<const int32_t> members, std::span<const int32_t> new_rows) {
  std::vector<BundleId> bundles;
  std::vector<int32_t> equalities, rows;
  for (int32_t s : members) {
    const SheetSubproblem& old = *subproblems_[s];
    bundles.insert(bundles.end(), old.bundles().begin(), old.bundles().end());
    equalities.insert(equalities.end(), old.equalities().begin(), old.equalities().end());
    rows.insert(rows.end(), old.rows().begin(), old.rows().end());
  }
  rows.insert(rows.end(), new_rows.begin(), new_rows.end());
  std::sort(bundles.begin(), bundles.end());
  const int32_t merged = static_cast<int32_t>(subproblems_.size());
  for (BundleId b : bundles) subproblem_of_bundle_[b] = merged;
  for (int32_t s : members) subproblems_[s].reset();
  subproblems_.push_back(std::make_unique<SheetSubproblem>(&context_, std::move(bundles),
                                                           std::move(equalities), std::move(rows)));
}

}  // namespace ispq
