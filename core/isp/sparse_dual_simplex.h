// SPDX-License-Identifier: Apache-2.0
// A bounded dual simplex whose work per solve is proportional to the pivots it makes, for LPs
// that are solved thousands of times after small edits (the sheet LPs of core/isp/sheet_lp.h).
//
// A general-purpose solver such as CLP restarts each solve with work over the whole model:
// duals and reduced costs of every column, feasibility checks, its work areas. On a 100k-arc
// T-mesh that fixed part is ~10 ms per solve while the solve itself takes ~10 pivots. This
// solver keeps everything between solves and updates only what an edit or a pivot touches:
//
//   - the basis is factorized by CoinUtils' CoinFactorization (sparse LU with Forrest-Tomlin
//     updates, hypersparse solves), refactorized every max_pivots pivots;
//   - primal values and reduced costs are updated incrementally: an edit of a nonbasic bound
//     costs one FTRAN, an edit of a basic cost one BTRAN, a pivot a BTRAN, an FTRAN and the
//     pivot row over the rows the BTRAN reached;
//   - the primal infeasibilities are kept in a list, so choosing the leaving row (approximate
//     steepest edge) does not scan all rows;
//   - at the end of a solve the basic values are recomputed exactly from the nonzero nonbasic
//     ones, so that the rounding of the updates never reaches the answer.
//
// Work proportional to the model happens only on refactorization (every max_pivots pivots),
// when rows are added, and on a reset to the slack basis.
//
// The model: min c x subject to row_lower <= A x <= row_upper and column bounds. Internally each
// row i has a logical variable s_i = a_i x with the row's bounds, so the constraints read
// [A | -I] (x, s) = 0 and the slack basis -I is always a basis. The solver needs a dual feasible
// basis to start from: it keeps the last optimal one, and falls back to the slack basis, which
// is dual feasible whenever every column has a finite bound on the side its cost pushes it to
// (c >= 0 with a finite lower bound, as in the sheet LPs). A warm basis that an edit made dual
// infeasible is repaired by moving the offending columns to their other bound (an artificial one
// if they have none, as CLP does), else replaced by the slack basis.
//
// Not a general LP solver: no primal simplex, no unboundedness detection beyond what the dual
// simplex sees, no presolve or scaling. Solve() reports kFailed when it cannot finish (the
// iteration limit or repeated numerical trouble); callers fall back to a general solver.
#ifndef ISPQ_CORE_ISP_SPARSE_DUAL_SIMPLEX_H_
#define ISPQ_CORE_ISP_SPARSE_DUAL_SIMPLEX_H_

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/isp/sheet_lp.h"

class CoinFactorization;
class CoinIndexedVector;

namespace ispq {

struct SparseDualSimplexOptions {
  // Forrest-Tomlin updates between refactorizations.
  int max_pivots = 400;
  // A basic variable further than this outside its bounds is infeasible, and one this close to a
  // bound is put on it (absolute: the sheet LPs' primal values are small rationals).
  double primal_tolerance = 1e-8;
  // Dual feasibility: absolute, plus 1e-14 |cost| of the variable, the rounding its reduced cost
  // carries (the sheet weights span 1e-3..1e20, and eq. 4's tiers must stay apart).
  double dual_tolerance = 1e-9;
  // Pivot row entries smaller than this never enter.
  double pivot_tolerance = 1e-9;
  // Where a dual infeasible column without a finite upper bound is put so that the dual simplex
  // can go on (CLP's "dual bound"); a solve that ends with a column still there reports kFailed.
  double artificial_bound = 1e3;
  // Pivots of one Solve() before it gives up with kFailed.
  int64_t max_iterations = 200000;
  // Consecutive dual degenerate pivots (a dual step of zero: the objective does not move) after
  // which Solve() takes the LP for stalled, possibly cycling, and gives up with kFailed, so that
  // the caller's general solver (CLP, which perturbs costs) takes it. On the 62 real T-meshes at
  // all 8 levels and on 100k-arc benchmark parts, no run was longer than 2 pivots (the sheet
  // weights make exact ties rare); a cycle would go on forever.
  int64_t max_degenerate_pivots = 1000;
  // A solve after a new objective (most_costs_changed()) that needs more pivots than
  // max(new_objective_min_pivots, new_objective_pivots_per_row * rows) is handed to CLP by the
  // sheet LP on this simplex (dual_simplex_sheet_lp.h).
  int64_t new_objective_min_pivots = 1000;
  double new_objective_pivots_per_row = 0.1;
  // A new objective on an LP of at least this many columns goes to CLP at once: there the pivot
  // budget above is mostly spent before CLP is called anyway (the bulk descent's LPs over a whole
  // 100k-arc part need 5-20k pivots from the slack basis), and the sheet LP takes CLP's optimal
  // basis back (AdoptBasis). On the 100k-arc benchmark parts 8-20% less CPU, same q; at 30k equal.
  int new_objective_clp_min_columns = 4000;
  // A warm solve (no new objective) on an LP of at least warm_budget_min_columns columns is handed
  // to CLP once its work (SparseDualSimplex::work()) passes warm_budget_factor times what CLP's
  // last solve from scratch of this LP is estimated to cost: pivots^2 / clp_pivots_squared_per_work
  // (measured on the bulk LPs of 300k- and 10^6-arc parts: CLP's CPU time from scratch is
  // 2.1-3.5e-9 s times its pivots squared, a unit of work here 77-270 ns; see
  // tests/bench/large/results/assembly/README.md).
  int warm_budget_min_columns = 150000;
  double warm_budget_factor = 2;
  double clp_pivots_squared_per_work = 40;
};

class SparseDualSimplex {
 public:
  // kStopped: the stop check (SetStopCheck) held; the solve can be repeated from where it ended.
  enum class Status : uint8_t { kOptimal, kInfeasible, kFailed, kStopped };

  // num_columns columns with bounds [0, +inf), cost 0, and no rows.
  explicit SparseDualSimplex(int num_columns, const SparseDualSimplexOptions& options = {});
  ~SparseDualSimplex();
  SparseDualSimplex(const SparseDualSimplex&) = delete;
  SparseDualSimplex& operator=(const SparseDualSimplex&) = delete;

  int num_columns() const { return num_columns_; }
  int num_rows() const { return num_rows_; }

  void SetObjectiveCoefficient(int column, double value);
  void SetColumnBounds(int column, double lower, double upper);
  void SetRowBounds(int row, double lower, double upper);
  // Appends rows; they get the ids num_rows() .. num_rows() + batch.size() - 1.
  void AddRows(const LpRowBatch& batch);

  // kFailed after max_iterations pivots (options' limit when 0 or larger), or once the solve's
  // work (see work()) passes max_work (no limit when 0).
  Status Solve(int64_t max_iterations = 0, int64_t max_work = 0);
  // Polled every kPassesBetweenStopChecks passes of Solve()'s loop (about as many pivots): a
  // solve ends with kStopped once it holds. Empty: never stops early.
  void SetStopCheck(LpStopCheck should_stop) { should_stop_ = std::move(should_stop); }
  static constexpr int64_t kPassesBetweenStopChecks = 64;
  // Takes the basis another solver found optimal for the model as it stands: `is_basic` flags the
  // columns and then the rows' logicals (exactly num_rows() of them set), `column_values` that
  // solver's answer, which puts each nonbasic variable at the bound it is nearest to. The next
  // Solve() factorizes it and goes on from there, warm, instead of from wherever this simplex
  // stopped (a singular basis falls back to the slack basis).
  void AdoptBasis(std::span<const uint8_t> is_basic, std::span<const double> column_values);
  // Whether most costs changed since the last solve (a new objective): Solve() would then start
  // from the slack basis, dual feasible for any non-negative costs, since repairing the dual
  // feasibility of the old basis column by column takes longer.
  bool most_costs_changed() const;
  // Column values of the last kOptimal solve.
  std::span<const double> column_values() const {
    return {value_.data(), static_cast<size_t>(num_columns_)};
  }
  // Appends the columns with a non-zero value, in any order: work proportional to them.
  void AppendNonzeroColumns(std::vector<int32_t>* columns) const;
  // The model as it stands, for a fallback solver.
  double objective(int column) const { return cost_[column]; }
  double lower(int variable) const { return lower_[variable]; }
  double upper(int variable) const { return upper_[variable]; }
  std::span<const int32_t> row_starts() const { return row_start_; }
  std::span<const int32_t> row_columns() const { return row_column_; }
  std::span<const double> row_coefs() const { return row_coef_; }

  // For tests: the kept values and reduced costs against ones recomputed from the current
  // factorization (the state is left as it was).
  struct ScratchCheck {
    double value_drift = 0;           // largest |kept - recomputed| value
    double primal_infeasibility = 0;  // of the recomputed basic values
    int dual_infeasible = 0;          // nonbasic variables with a wrong-signed recomputed d
  };
  ScratchCheck CheckAgainstScratch();

  // Counters since construction.
  int64_t iterations() const { return iterations_; }
  int64_t degenerate_pivots() const { return degenerate_pivots_; }
  // A deterministic measure of the work done so far, proportional to CPU time: the entries of
  // every pivot's BTRAN, FTRAN and pivot row, and the rows of every refactorization.
  int64_t work() const { return work_done_; }
  int64_t stalled_solves() const { return stalled_solves_; }
  int64_t refactorizations() const { return refactorizations_; }
  const SparseDualSimplexOptions& options() const { return options_; }

 private:
  enum class VarStatus : uint8_t { kBasic, kAtLower, kAtUpper, kFree };
  // Variables 0..n-1 are columns, n..n+m-1 the rows' logicals.
  int num_variables() const { return num_columns_ + num_rows_; }
  bool IsLogical(int v) const { return v >= num_columns_; }

  // --- basis and factorization
  // Factorizes the current basis and recomputes primal values and reduced costs from scratch;
  // false if the basis is singular (the caller resets to the slack basis).
  bool Refactorize();
  void ResetToSlackBasis();
  void RecomputePrimalValues();
  // The basic values from scratch over the kept lists of nonzero values (see below).
  void RecomputeBasicValues();
  void NoteBasicValue(int position);
  void NoteNonbasicValue(int v);
  void RecomputeReducedCosts();
  // Adds column `v` of [A | -I] times `scale` to a row-indexed vector.
  void AddColumnTo(int v, double scale, CoinIndexedVector* vector) const;
  // y^T [A | -I] over the nonbasic variables, entry by entry: share(v, a_iv * y_i) for every
  // row i where y is not noise and every nonbasic v in that row (summed per v: col_v^T y). Work
  // proportional to the rows y reaches.
  template <typename Share>
  void ForEachNonbasicShare(const CoinIndexedVector& y, Share&& share) const;

  // --- edits
  // Puts nonbasic v at the bound its reduced cost prefers (or its only finite one).
  void PlaceNonbasic(int v);
  void MoveNonbasicTo(int v, double value);
  void ApplyPendingPrimalChange();
  void ApplyPendingCostChange();
  // Moves dual infeasible nonbasic variables to their other bound; false if one cannot move.
  bool RepairDualFeasibility();
  // Whether no column is left at the artificial bound.
  bool LeftArtificialBounds();
  bool DualInfeasible(int v) const;

  // --- iterations
  void MarkPrimalCandidate(int position);
  // The basis position of the most infeasible basic variable, or -1.
  int ChooseLeavingPosition();
  void ComputePivotRow(int position);
  // Recomputes the leaving variable's value from the pivot row; false if it is feasible after all
  // (the pivot row is dropped then).
  bool RefreshLeavingValue(int position);
  // The entering variable for a leaving variable below (+1) or above (-1) its bounds, or -1.
  int ChooseEntering(int direction, double* dual_step);
  // One pivot; false if the factorization must be rebuilt first.
  bool Pivot(int position, int entering, int direction, double dual_step);
  double Infeasibility(int v) const;
  double DualTolerance(int v) const;
  // core/invariant.h checks: the basis matches the statuses; an optimal answer is feasible.
  void CheckBasisInvariants() const;
  void CheckOptimalInvariants() const;

  const SparseDualSimplexOptions options_;
  LpStopCheck should_stop_;
  int num_columns_;
  int num_rows_ = 0;

  // The matrix by rows (appended) and by columns (rebuilt when rows are added).
  std::vector<int32_t> row_start_{0};
  std::vector<int32_t> row_column_;
  std::vector<double> row_coef_;
  std::vector<int32_t> column_start_;
  std::vector<int32_t> column_row_;
  std::vector<double> column_coef_;
  // A row being added, while its repeated columns are merged.
  struct ColumnTerm {
    int32_t var;
    double coef;
  };
  std::vector<ColumnTerm> new_row_;

  // Per variable.
  std::vector<double> lower_, upper_, cost_;
  std::vector<double> value_;
  std::vector<double> reduced_cost_;
  std::vector<VarStatus> status_;
  std::vector<int32_t> position_;  // basis position, or -1
  // Pricing weights of the basic variables, estimates of the steepest-edge norms |e_p^T B^-1|^2:
  // the leaving row maximizes infeasibility^2 / weight. Exact for the slack basis (1); after a
  // pivot the leaving row's is exact (|rho|^2, at hand) and the others are updated as in Devex
  // (Forrest-Goldfarb's exact update needs B^-1 rho, an FTRAN whose result is dense at scale:
  // 7000 nonzeros a pivot on a 100k-arc part, 40% of the time, for 2% fewer pivots). Kept
  // across refactorizations.
  std::vector<double> edge_weight_;
  // Columns moved to the artificial bound since the last optimal solve.
  std::vector<int32_t> at_artificial_bound_;
  // Per basis position.
  std::vector<int32_t> basic_variable_;

  std::unique_ptr<CoinFactorization> factorization_;
  bool factorization_valid_ = false;
  // The basis as triplets for CoinFactorization, and the permutation it answers: kept from one
  // refactorization to the next like the factorization's own arrays, so that each one refills
  // them instead of allocating (and, at scale, mapping and faulting in) megabytes anew.
  struct BasisTriplets {
    std::vector<int32_t> basics, rows, columns, permutation;
    std::vector<double> elements;
  };
  BasisTriplets basis_triplets_;
  // Work vectors for the factorization (row- or position-indexed, m + max_pivots long).
  std::unique_ptr<CoinIndexedVector> work_, column_, row_, pending_primal_, pending_cost_;
  bool has_pending_primal_ = false;
  bool has_pending_cost_ = false;

  // Basis positions and nonbasic variables whose values may be nonzero (lazily cleaned), so that
  // the basic values can be recomputed exactly at the end of a solve in time proportional to
  // them: the incremental updates drift by ~1e-9 per hundred pivots, and a drift of 1e-9 on a
  // column of weight 1e9 is a unit of objective.
  std::vector<int32_t> nonzero_basic_, nonzero_nonbasic_;
  std::vector<uint8_t> is_nonzero_basic_, is_nonzero_nonbasic_;
  // Nonbasic variables whose reduced cost or bounds changed since the last solve.
  std::vector<int32_t> dual_check_;
  // Basis positions whose value or weight changed since the leaving row was last chosen, and a
  // max-heap of the infeasible positions by their leaving score (ChooseLeavingPosition). A
  // position's entries go stale when it is scored again (its stamp moves on).
  std::vector<int32_t> primal_candidates_;
  std::vector<uint8_t> is_primal_candidate_;
  struct LeavingCandidate {
    double score;
    int32_t variable;
    int32_t position;
    uint32_t stamp;
  };
  std::vector<LeavingCandidate> leaving_heap_;
  std::vector<uint32_t> leaving_stamp_;  // by position
  // The pivot row over nonbasic variables: dense by variable, with the touched list.
  std::vector<double> alpha_;
  std::vector<int32_t> alpha_touched_;

  int64_t costs_changed_ = 0;  // since the last solve
  int64_t iterations_ = 0;
  int64_t work_done_ = 0;
  int64_t degenerate_pivots_ = 0;
  int64_t stalled_solves_ = 0;
  int64_t refactorizations_ = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SPARSE_DUAL_SIMPLEX_H_
