// SPDX-License-Identifier: Apache-2.0
// SheetLp (core/isp/sheet_lp.h) on the sparse dual simplex of core/isp/sparse_dual_simplex.h,
// the back end for large subproblems: its cost per solve follows the pivots, not the model.
//
// A solve the sparse simplex cannot finish (its iteration limit, repeated numerical trouble) is
// handed to CLP on a copy of the model built for that solve, so every solve still gets an
// answer. So is a solve after a new objective that needs many pivots from the slack basis, where
// CLP is faster (SparseDualSimplexOptions::new_objective_min_pivots), and, on a very large LP, a
// warm solve that has done more work than a multiple of what CLP's last solve from scratch of it
// is estimated to cost (SparseDualSimplexOptions::warm_budget_factor).
#ifndef ISPQ_CORE_ISP_DUAL_SIMPLEX_SHEET_LP_H_
#define ISPQ_CORE_ISP_DUAL_SIMPLEX_SHEET_LP_H_

#include <memory>

#include "core/isp/sheet_lp.h"
#include "core/isp/sparse_dual_simplex.h"

namespace ispq {

std::unique_ptr<SheetLp> NewDualSimplexSheetLp(int num_columns,
                                               const SparseDualSimplexOptions& options = {});

// The factory the engine is given by default: NewDualSimplexSheetLp with these options.
SheetLpFactory DualSimplexSheetLpFactory(const SparseDualSimplexOptions& options = {});

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_DUAL_SIMPLEX_SHEET_LP_H_
