// SPDX-License-Identifier: Apache-2.0
// The constraints of the quantization problem (paper eq. 1b-1d) over arc bundles, as the exact
// mode and the lower bound state them (core/README.md, section Exact mode):
//   - the consistency rows that bundling leaves (equalities, deduplicated);
//   - the simple rows (proto/README.md, sections Non-negativity and Separation): block extents >= 0
//     (C), critical links of positive length, critical regions not collapsed, and q_a >= 0 per arc
//     if asked. Every valid q satisfies them, so they are part of the problem from the start, as in
//     the reference's IQP variant;
//   - the separation rows found so far (eq. 1c), each in its default form with its failsafe
//     twin B+ (paper App. B) kept to stand in for it.
// Rows read sum coef * x_b >= rhs (inequalities) or sum coef * x_b = 0 (equalities).
#ifndef ISPQ_CORE_EXACT_QUANTIZATION_CONSTRAINTS_H_
#define ISPQ_CORE_EXACT_QUANTIZATION_CONSTRAINTS_H_

#include <cstdint>
#include <optional>
#include <set>
#include <span>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/flat_lists.h"
#include "core/separation_row.h"
#include "core/tmesh.h"

namespace ispq {

class QuantizationConstraints {
 public:
  // `bundles` must outlive this object.
  QuantizationConstraints(const TMesh& mesh, const ConsistencyMatrix& consistency,
                          const ArcBundles& bundles, bool per_arc_nonnegative);

  int num_equalities() const { return equalities_.size(); }
  std::span<const LinearTerm> equality(int i) const { return equalities_[i]; }
  int num_inequalities() const { return static_cast<int>(inequalities_.size()); }
  std::span<const LinearTerm> inequality(int i) const { return inequalities_[i]; }
  int64_t rhs(int i) const { return rhs_[i]; }
  int num_separation_rows() const { return static_cast<int>(failsafe_.size()); }
  // The separation rows in the form now in force, over arcs (each bundle as its smallest arc).
  std::vector<SeparationRow> SeparationRowsOverArcs() const;

  // Adds a separation row given over arcs with its failsafe twin (nullopt: the row is its own
  // twin). A default row that bundling empties can never hold; its twin is used instead. Returns
  // false if the row was already present.
  bool AddSeparationRow(const SeparationRow& row, const std::optional<SeparationRow>& failsafe);
  // Replaces every separation row by its failsafe twin (App. B), for when the default rows
  // together admit no q at all.
  void UseFailsafeForms();

  // Whether bundle values x satisfy every row exactly.
  bool SatisfiedBy(std::span<const int64_t> x) const;
  // Whether they satisfy the consistency and simple rows, i.e. everything but the separation
  // rows: then the separation search may judge them.
  bool SatisfiesFixedRows(std::span<const int64_t> x) const;
  // The bundle values of a q given per arc (each bundle's first arc), and back.
  std::vector<int64_t> BundleValues(std::span<const int64_t> q) const;
  std::vector<int64_t> ArcValues(std::span<const int64_t> x) const;

 private:
  // Appends the row over bundles unless an identical one exists; true if appended.
  bool AddInequality(std::span<const LinearTerm> terms, int64_t rhs);
  static int64_t Value(std::span<const LinearTerm> terms, std::span<const int64_t> x);

  const ArcBundles& bundles_;
  FlatLists<LinearTerm> equalities_;
  std::vector<std::vector<LinearTerm>> inequalities_;
  std::vector<int64_t> rhs_;
  int num_fixed_inequalities_ = 0;        // the simple rows come first
  std::set<std::vector<int64_t>> known_;  // (var, coef)..., rhs of every inequality
  // Per separation row: its inequality index, and its failsafe twin over bundles.
  std::vector<int> separation_index_;
  std::vector<std::vector<LinearTerm>> failsafe_;
  std::vector<int64_t> failsafe_rhs_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_QUANTIZATION_CONSTRAINTS_H_
