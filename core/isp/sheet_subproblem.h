// SPDX-License-Identifier: Apache-2.0
// The sheet LP of one independent subproblem (paper App. A with the decomposition of section 4.4),
// built once and then edited in place between solves (core/README.md, section Sheet LPs).
//
// Columns: two per bundle of the subproblem, Delta+ (column 2i) and Delta- (column 2i + 1), both
// >= 0, so that a sheet is Delta+ - Delta-. Rows: the subproblem's consistency rows over bundles
// (eq. 7b, after bundle elimination), then its inequality rows (eqs. 7c/7d) in the order they were
// added, each as sum coef (Delta+ - Delta-) >= rhs - value(q_pre). Between solves only what
// changed is pushed to the solver: the weights (eq. 4) of bundles that moved, the bounds of rows
// whose value or activity changed, the bounds of the root columns (eqs. 7e/7f) and, when the
// mode changes, the Delta+/Delta- upper bounds (uniform-sign and non-deflating modes, eq. 7g).
// Everything that stays is left to the solver's warm start.
//
// For LPs that want it (SheetLp::wants_column_cap, i.e. CLP), the columns are capped at a large
// finite value (SheetLpContext::column_cap) instead of being unbounded. With unbounded columns,
// every weight change that leaves the warm basis dual infeasible makes CLP's dual simplex put
// artificial bounds on the columns and then clean up with a primal simplex that refactorizes the
// whole basis: half of the CPU time on a 10k-arc mesh. With boxed columns the dual simplex repairs
// dual infeasibilities by bound flips. The cap never cuts off an answer: a solve whose solution
// reaches it, or that the cap makes infeasible, is repeated with the cap lifted, and an LP optimum
// strictly inside the box is an optimum without it (among tied optima the solver may pick another
// vertex, as any warm start may).
//
// On meshes whose consistent q are potential differences, a large subproblem's requests without a
// root (the bulk descent, separating updates) are first put to a min-cost flow
// (core/isp/sheet_network.h, SheetLpContext::potentials); the LP answers where the flow cannot.
#ifndef ISPQ_CORE_ISP_SHEET_SUBPROBLEM_H_
#define ISPQ_CORE_ISP_SHEET_SUBPROBLEM_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/flat_lists.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/integer_sheet.h"
#include "core/isp/sheet_infeasibility.h"
#include "core/isp/sheet_lp.h"
#include "core/isp/sheet_lp_context.h"
#include "core/isp/sheet_network.h"
#include "core/isp/sheet_request.h"
#include "core/isp/sheet_weights.h"

namespace ispq {

// The rational solution of a solve: bundles with a non-zero Delta+ - Delta-, ascending.
struct RationalSheet {
  std::vector<BundleId> bundles;
  std::vector<double> values;
};

class SheetSubproblem {
 public:
  // `bundles` ascending; `equalities` and `rows` are ids into the context's stores, all over
  // these bundles only.
  SheetSubproblem(SheetLpContext* context, std::vector<BundleId> bundles,
                  std::vector<int32_t> equalities, std::vector<int32_t> rows);

  const std::vector<BundleId>& bundles() const { return bundles_; }
  const std::vector<int32_t>& equalities() const { return equalities_; }
  const std::vector<int32_t>& rows() const { return rows_; }

  // Appends inequality rows (already in the context's store, over this subproblem's bundles).
  void AddRows(std::span<const int32_t> rows);
  // Bundle b moved: its weights and the bounds of its rows must be refreshed before the next solve.
  void MarkBundleMoved(BundleId b);
  // Row r changed activity.
  void MarkRowChanged(int32_t r);

  // false if the LP is infeasible, or if its solve was stopped (SheetLp::SetStopCheck: the run's
  // clock, which the caller asks next); on success `sheet` holds the solution. Requests that are
  // infeasible on their face (a root or pinned bundle below its floor) do not reach the solver.
  absl::StatusOr<bool> Solve(const SheetRequest& request, RationalSheet* sheet);
  // How many times Solve() actually ran the solver, how many of those were repeats with the
  // column cap lifted, and how many requests bound propagation refuted without the solver
  // (core/isp/sheet_infeasibility.h).
  int64_t solver_calls() const { return solver_calls_; }
  // What the LP back ends of this subproblem did in its solves (its LP may have been rebuilt).
  const SheetLpCounters& lp_counters() const { return lp_counters_; }
  int64_t uncapped_solves() const { return uncapped_solves_; }
  // Of the solver runs, requests without a root that a flow answered (SheetLpContext::potentials).
  int64_t flow_solves() const { return flow_solves_; }
  int64_t refuted_requests() const { return refuted_requests_; }

  // Whether an integer sheet over these bundles satisfies every consistency row exactly.
  bool IsConsistent(const IntegerSheet& sheet);

 private:
  void Build();
  void AppendRow(std::span<const LinearTerm> terms, double lower, double upper, LpRowBatch* batch);
  double RowLowerBound(int32_t r) const;
  void PushRowBounds(int32_t r);
  void PushWeights(BundleId b);
  void SetMode(bool allow_inflation, bool allow_deflation);
  // Weights of moved bundles and bounds of changed rows, pushed to the solver.
  void PushPendingEdits(WeightScheme weights);
  // Sets the column bounds a request asks for; false if it is infeasible on its face.
  bool SetRequestBounds(const SheetRequest& request);
  // A request for unit moves (SheetRequest::unit_moves): every column boxed at one unit.
  absl::StatusOr<bool> SolveUnitMoves(const SheetRequest& request, RationalSheet* sheet);
  // A request without a root as a flow (core/isp/sheet_network.h), every move within
  // -bound..bound; nullopt if the flow gives no answer and the LP must.
  std::optional<bool> SolveAsFlow(const SheetRequest& request, double bound, RationalSheet* sheet);
  // Bundle b's weights in the current scheme.
  BundleWeights WeightsOf(BundleId b) const;
  // Runs the solver and counts what it did.
  absl::StatusOr<LpOutcome> RunSolver();
  // Reads the last solution into `sheet`; returns whether some column of it sits at the cap.
  bool ReadSheet(RationalSheet* sheet);
  // The column cap outside a repeat without it: the context's if the LP wants one, else +inf.
  double UsualCap() const;
  // Sets every column pair's bounds for the current mode and cap.
  void ResetAllColumnPairs();
  void ResetColumnPair(int32_t local);
  // How far bundle b may deflate on its own: its value if it has a floor row, else +inf.
  double DeflationCap(BundleId b) const;

  SheetLpContext* context_;
  std::vector<BundleId> bundles_;
  std::vector<int32_t> equalities_;
  std::vector<int32_t> rows_;
  FlatLists<int32_t> equalities_of_bundle_;  // by local index: positions in equalities_
  std::unique_ptr<SheetLp> lp_;
  std::unique_ptr<SheetNetwork> network_;            // made by the first request a flow answers
  std::vector<BundleWeights> network_weights_;       // scratch of SolveAsFlow
  std::vector<std::pair<BundleId, int64_t>> moves_;  // scratch of SolveAsFlow
  SheetInfeasibility infeasibility_;

  std::vector<BundleId> dirty_bundles_;
  std::vector<uint8_t> bundle_dirty_;  // by local index
  std::vector<int32_t> dirty_rows_;
  bool allow_inflation_ = true, allow_deflation_ = true;
  // The context's column_cap if the LP wants it, +inf otherwise and during a repeat without it.
  double cap_;
  WeightScheme weights_ = WeightScheme::kTiered;
  int32_t root_local_ = kNoId;
  std::vector<int32_t> blocked_locals_;   // column pairs whose bounds a request changed
  std::vector<int64_t> scratch_delta_;    // by local index, for IsConsistent
  std::vector<int32_t> nonzero_columns_;  // scratch for ReadSheet
  std::vector<int32_t> columns_;          // scratch for AppendRow
  std::vector<double> coefs_;
  int64_t solver_calls_ = 0;
  SheetLpCounters lp_counters_;
  int64_t uncapped_solves_ = 0;
  int64_t refuted_requests_ = 0;
  int64_t flow_solves_ = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_SUBPROBLEM_H_
