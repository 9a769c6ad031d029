// SPDX-License-Identifier: Apache-2.0
// The solver interface the exact mode is written against: a MILP solve that reports each new
// incumbent and its progress as it goes (so that the lazy separation loop can check incumbents
// while the search runs and the service can stream them), and the LP relaxation of the same
// model (the lower bound of every result). Implementation: core/exact/cbc_milp_solver.h
// (COIN-OR CBC, with CLP for the relaxation).
#ifndef ISPQ_CORE_EXACT_MILP_SOLVER_H_
#define ISPQ_CORE_EXACT_MILP_SOLVER_H_

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "absl/status/statusor.h"
#include "core/exact/milp_model.h"

namespace ispq {

// What the caller learns while a MILP solve runs. Either callback returning false stops the
// solve at the solver's next opportunity.
class MilpCallbacks {
 public:
  virtual ~MilpCallbacks() = default;
  // A new incumbent: column values and objective (offset included).
  virtual bool OnIncumbent(std::span<const double> columns, double objective) = 0;
  // Called regularly (at least once per branch-and-bound node) with the proven lower bound.
  virtual bool OnProgress(double bound, int64_t nodes) = 0;
};

struct MilpSolveOptions {
  double time_limit_seconds = std::numeric_limits<double>::infinity();
  // Only solutions with objective < cutoff are sought; a solve that finds none is kInfeasible.
  double cutoff = std::numeric_limits<double>::infinity();
  // A feasible solution to start from (its objective below `cutoff` is not required).
  std::optional<std::vector<double>> initial_solution;
  // The search stops when incumbent - bound <= max(absolute_gap, relative_gap * |incumbent|).
  double absolute_gap = 1e-7;
  double relative_gap = 1e-9;
};

enum class MilpStatus : uint8_t {
  kOptimal,     // the best solution is optimal within the gap tolerances
  kInfeasible,  // no solution below the cutoff exists
  kStopped,     // time limit or a callback stopped it; `bound` is what was proven
};

struct MilpResult {
  MilpStatus status = MilpStatus::kStopped;
  std::optional<std::vector<double>> best;  // the best solution seen (also the initial one)
  double best_objective = std::numeric_limits<double>::infinity();
  // No solution below the cutoff has a smaller objective; -inf if nothing was proven.
  double bound = -std::numeric_limits<double>::infinity();
  int64_t nodes = 0;
};

enum class LpStatus : uint8_t { kOptimal, kInfeasible };

struct LpResult {
  LpStatus status = LpStatus::kInfeasible;
  double objective = 0;  // offset included
};

class MilpSolver {
 public:
  virtual ~MilpSolver() = default;
  // An error only when the solver fails (numerical trouble, an unbounded relaxation).
  virtual absl::StatusOr<MilpResult> Solve(const MilpModel& model, const MilpSolveOptions& options,
                                           MilpCallbacks& callbacks) = 0;
  // The model with integrality dropped.
  virtual absl::StatusOr<LpResult> SolveRelaxation(const MilpModel& model) = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_MILP_SOLVER_H_
