// SPDX-License-Identifier: Apache-2.0
// SheetLp (core/isp/sheet_lp.h) on COIN-OR CLP, the open-source simplex solver the paper uses
// (core/README.md, section LP back ends).
//
// One ClpSimplex object lives as long as the SheetLp: edits go straight into it and every
// Solve() restarts the simplex from the previous basis (and, when the row count is unchanged,
// from the previous factorization), which is what makes hundreds of solves of the same small
// model cheap. CLP's own logging is silenced unless a log level is asked for.
#ifndef ISPQ_CORE_ISP_CLP_SHEET_LP_H_
#define ISPQ_CORE_ISP_CLP_SHEET_LP_H_

#include <cstdint>
#include <memory>

#include "core/isp/sheet_lp.h"

namespace ispq {

enum class ClpAlgorithm : uint8_t {
  kPrimal,  // primal simplex: the basis stays optimal-ish after objective-only edits
  kDual,    // dual simplex: the basis stays dual feasible after bound-only edits
};

// How CLP's dual simplex picks the row that leaves the basis.
enum class ClpDualPricing : uint8_t {
  // CLP's default: steepest edge, partial at first, exact weights once that pays.
  kClpDefault,
  // Steepest edge with every weight started at one (ClpDualRowSteepest mode 0), updated exactly
  // from there: no initial weights to compute and no switch of mode on the way.
  kSteepestEdgeFromUnitWeights,
};

struct ClpSheetLpOptions {
  int log_level = 0;
  ClpAlgorithm algorithm = ClpAlgorithm::kDual;
  // Keep CLP's work areas and factorization between solves (startFinishOptions 1 | 2), and skip
  // re-creating the work arrays the edits already updated in place (4): the set-up of a solve is
  // O(columns) whatever the few iterations cost (4 alone: 12% less CPU on a 10k-arc mesh).
  bool keep_factorization = true;
  // Pivots between refactorizations. A back end that lives across thousands of warm solves of a
  // few pivots each piles up updates: 100 there (CLP's default is 200; on the 100k-arc mesh at
  // level 5, 122 -> 90 s CPU, the same objective). A fresh model solved once from scratch wants
  // more (DualSimplexSheetLp's fallback: see dual_simplex_sheet_lp.cc).
  int factorization_frequency = 100;
  // A fresh model solved once from scratch wants kSteepestEdgeFromUnitWeights: on the whole-part
  // LP of a 300k-arc part (70k rows) CLP's default took 21.6k pivots and 22.4 s, this 20.4k pivots
  // and 14.2 s; on a 10^6-arc part's (224k rows) 71k pivots and ~280 s against 68k and 202 s, the
  // same optimum (core/README.md, section Sheet LPs as flows, Handles).
  ClpDualPricing dual_pricing = ClpDualPricing::kClpDefault;
};

// A SheetLp with num_columns columns in [0, +inf), objective 0, and no rows.
std::unique_ptr<SheetLp> NewClpSheetLp(int num_columns, const ClpSheetLpOptions& options = {});

// The factory the engine is given: NewClpSheetLp with these options.
SheetLpFactory ClpSheetLpFactory(const ClpSheetLpOptions& options = {});

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_CLP_SHEET_LP_H_
