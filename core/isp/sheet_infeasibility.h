// SPDX-License-Identifier: Apache-2.0
// Proves a sheet request infeasible without solving its LP, by bound propagation (core/README.md,
// section Refutation without an LP).
//
// In the thorough pass of a large part about half of the sheet LPs are infeasible: deflating a
// bundle that is already at zero (or one a separation row needs) forces, through the T-junction
// rows, some neighbour below its floor. Such a request is usually refuted by interval
// arithmetic alone: start from the request's bounds on the bundle moves Delta_b (the root moved
// by at least one unit, blocked directions, pinned bundles, the mode's sign restrictions, the
// floors Delta_b >= -x_b) and tighten them through the consistency rows (sum = 0) and the active
// inequality rows (sum >= -slack), as MIP presolvers do, until some interval is empty. The
// propagation is sound for the LP (continuous bounds, no rounding): it never refutes a request
// whose LP has a solution, so skipping such LPs changes no answer. It is not complete; what it
// cannot refute goes to the LP. Its work is bounded per request and follows the rows it
// tightens, not the size of the subproblem, and so is its memory: rows are told apart by their
// row in the subproblem's LP, never by their id in the whole mesh (a run has one of these per
// subproblem: with arrays over the whole mesh's rows, 8000 disjoint cubes took 4.6 GB more).
#ifndef ISPQ_CORE_ISP_SHEET_INFEASIBILITY_H_
#define ISPQ_CORE_ISP_SHEET_INFEASIBILITY_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/arc_bundles.h"
#include "core/flat_lists.h"
#include "core/isp/sheet_lp_context.h"
#include "core/isp/sheet_request.h"

namespace ispq {

class SheetInfeasibility {
 public:
  // Row visits one request may spend before it gives up (and the LP decides).
  static constexpr int kMaxRowVisits = 4096;

  // Over the bundles of one subproblem, its consistency rows (their ids in the context's store,
  // in the order of its LP's first rows) and, per bundle, the positions in `equalities` of those
  // through it; all must outlive this.
  SheetInfeasibility(const SheetLpContext* context, std::span<const BundleId> bundles,
                     std::span<const int32_t> equalities,
                     const FlatLists<int32_t>* equalities_of_bundle);

  // Whether no sheet satisfies the request: true only if its LP is infeasible.
  bool Refutes(const SheetRequest& request);

 private:
  struct Interval {
    double lower, upper;
  };
  // The bounds of local bundle i under the request, as tightened so far.
  Interval& Bounds(int32_t i);
  // The least move bundle b's floor row allows (Delta_b >= -x_b), -inf without one.
  double Floor(BundleId b) const;
  // Tightens bundle i to [lower, upper]; false if its interval became empty.
  bool Tighten(int32_t i, double lower, double upper);
  // Queues the rows of local bundle i.
  void QueueRowsOf(int32_t i);
  // The LP row of a queued row code (2 * local equality, 2 * inequality row id + 1).
  int32_t LpRowOf(int32_t code) const;
  // Tightens the bundles of one row from the others; false if the row cannot hold.
  bool PropagateRow(std::span<const LinearTerm> terms, double lower, double upper);

  const SheetLpContext* context_;
  std::span<const BundleId> bundles_;
  std::span<const int32_t> equalities_;             // by local equality: its id in the context
  const FlatLists<int32_t>* equalities_of_bundle_;  // by local index: local equalities

  // Per request (stamped, so that nothing is cleared per request).
  const SheetRequest* request_ = nullptr;
  uint32_t stamp_ = 0;
  std::vector<uint32_t> bounds_stamp_;  // by local index
  std::vector<Interval> bounds_;
  std::vector<uint32_t> queued_stamp_;  // by LP row
  std::vector<int32_t> queue_;          // row codes: 2 * local equality, 2 * inequality id + 1
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_INFEASIBILITY_H_
