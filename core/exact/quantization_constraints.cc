// SPDX-License-Identifier: Apache-2.0
#include "core/exact/quantization_constraints.h"

#include "core/bundle_row_pair.h"
#include "core/simple_constraints.h"

namespace ispq {
namespace {

std::vector<int64_t> Key(std::span<const LinearTerm> terms, int64_t rhs) {
  std::vector<int64_t> key;
  key.reserve(2 * terms.size() + 1);
  for (const LinearTerm& t : terms) {
    key.push_back(t.var);
    key.push_back(t.coef);
  }
  key.push_back(rhs);
  return key;
}

}  // namespace

QuantizationConstraints::QuantizationConstraints(const TMesh& mesh,
                                                 const ConsistencyMatrix& consistency,
                                                 const ArcBundles& bundles,
                                                 bool per_arc_nonnegative)
    : bundles_(bundles) {
  std::set<std::vector<int64_t>> equalities;
  for (int r = 0; r < consistency.num_rows(); ++r) {
    std::vector<LinearTerm> terms = bundles.ToBundleTerms(consistency.row(r));
    if (terms.empty()) continue;
    // Rows equal up to sign are one equality (as in core/isp/subproblem_set.cc).
    if (terms[0].coef < 0) {
      for (LinearTerm& t : terms) t.coef = -t.coef;
    }
    if (!equalities.insert(Key(terms, 0)).second) continue;
    equalities_.Append(terms);
  }
  const std::optional<int64_t> arc_bound =
      per_arc_nonnegative ? std::optional<int64_t>(0) : std::nullopt;
  for (const SimpleRow& simple : BuildSimpleRows(mesh, arc_bound)) {
    AddInequality(bundles.ToBundleTerms(simple.row.terms), simple.row.rhs);
  }
  num_fixed_inequalities_ = num_inequalities();
}

bool QuantizationConstraints::AddInequality(std::span<const LinearTerm> terms, int64_t rhs) {
  // An empty row 0 >= rhs holds or never does; the callers never pass the latter.
  if (terms.empty() || !known_.insert(Key(terms, rhs)).second) return false;
  inequalities_.emplace_back(terms.begin(), terms.end());
  rhs_.push_back(rhs);
  return true;
}

bool QuantizationConstraints::AddSeparationRow(const SeparationRow& row,
                                               const std::optional<SeparationRow>& failsafe) {
  BundleRowPair pair = ToBundleRowPair(bundles_, row, failsafe.has_value() ? *failsafe : row);
  if (!AddInequality(pair.default_terms, pair.default_rhs)) return false;
  separation_index_.push_back(num_inequalities() - 1);
  failsafe_.push_back(std::move(pair.failsafe_terms));
  failsafe_rhs_.push_back(pair.failsafe_rhs);
  return true;
}

void QuantizationConstraints::UseFailsafeForms() {
  for (size_t i = 0; i < failsafe_.size(); ++i) {
    const int r = separation_index_[i];
    if (failsafe_[i].empty()) continue;
    inequalities_[r] = failsafe_[i];
    rhs_[r] = failsafe_rhs_[i];
  }
}

std::vector<SeparationRow> QuantizationConstraints::SeparationRowsOverArcs() const {
  std::vector<SeparationRow> rows;
  rows.reserve(separation_index_.size());
  for (const int r : separation_index_) {
    rows.push_back({.terms = bundles_.ToArcTerms(inequalities_[r]), .rhs = rhs_[r]});
  }
  return rows;
}

int64_t QuantizationConstraints::Value(std::span<const LinearTerm> terms,
                                       std::span<const int64_t> x) {
  int64_t sum = 0;
  for (const LinearTerm& t : terms) sum += t.coef * x[t.var];
  return sum;
}

bool QuantizationConstraints::SatisfiesFixedRows(std::span<const int64_t> x) const {
  for (int i = 0; i < num_equalities(); ++i) {
    if (Value(equalities_[i], x) != 0) return false;
  }
  for (int i = 0; i < num_fixed_inequalities_; ++i) {
    if (Value(inequalities_[i], x) < rhs_[i]) return false;
  }
  return true;
}

bool QuantizationConstraints::SatisfiedBy(std::span<const int64_t> x) const {
  if (!SatisfiesFixedRows(x)) return false;
  for (int i = num_fixed_inequalities_; i < num_inequalities(); ++i) {
    if (Value(inequalities_[i], x) < rhs_[i]) return false;
  }
  return true;
}

std::vector<int64_t> QuantizationConstraints::BundleValues(std::span<const int64_t> q) const {
  std::vector<int64_t> x(bundles_.num_bundles());
  for (BundleId b = 0; b < bundles_.num_bundles(); ++b) x[b] = q[bundles_.arcs(b)[0]];
  return x;
}

std::vector<int64_t> QuantizationConstraints::ArcValues(std::span<const int64_t> x) const {
  std::vector<int64_t> q(bundles_.bundle_of_arc().size());
  for (size_t a = 0; a < q.size(); ++a) q[a] = x[bundles_.bundle_of(static_cast<ArcId>(a))];
  return q;
}

}  // namespace ispq
