// SPDX-License-Identifier: Apache-2.0
// MilpSolver (core/exact/milp_solver.h) on COIN-OR CBC, the open-source branch-and-cut solver of
// the same family as the CLP the ISP engine uses; its LP relaxation is solved by CLP directly.
//
// Each Solve() builds a fresh CbcModel on an OsiClpSolverInterface with CBC's default cut
// generators and heuristics plus the two that use an incumbent (RINS, local search), without
// preprocessing, so that the columns CBC reports are the model's own. An event handler relays
// every incumbent and every node to the callbacks and stops the search when they ask. CBC's
// own output is silenced.
#ifndef ISPQ_CORE_EXACT_CBC_MILP_SOLVER_H_
#define ISPQ_CORE_EXACT_CBC_MILP_SOLVER_H_

#include <memory>

#include "core/exact/milp_solver.h"

namespace ispq {

std::unique_ptr<MilpSolver> NewCbcMilpSolver();

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_CBC_MILP_SOLVER_H_
