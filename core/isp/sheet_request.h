// SPDX-License-Identifier: Apache-2.0
// What one sheet LP solve asks for (paper App. A, C): the root and the direction it is pumped in
// (eqs. 7e/7f) or none for a separating solve, the weights, the sign restrictions of the mode (eq.
// 7g and uniform-sign sheets), and the bundles blocked in one direction or pinned to a value for
// this solve only (core/README.md, section Sheet LPs).
#ifndef ISPQ_CORE_ISP_SHEET_REQUEST_H_
#define ISPQ_CORE_ISP_SHEET_REQUEST_H_

#include <cstdint>
#include <span>
#include <utility>

#include "core/arc_bundles.h"

namespace ispq {

enum class WeightScheme : uint8_t {
  kTiered,        // eq. 4
  kMarginalCost,  // the bundles' exact objective change per unit (core/isp/sheet_weights.h)
  kUnitCost,      // the same, unfloored: negative for a move that improves (unit_moves)
};

struct SheetRequest {
  BundleId root = kNoId;  // the pumped bundle (7e/7f); kNoId for a separating solve
  WeightScheme weights = WeightScheme::kTiered;
  bool inflate_root = true;
  bool allow_inflation = true;  // Delta+ may be non-zero off the root
  bool allow_deflation = true;  // Delta- may be non-zero off the root (false: eq. 7g)
  // Bundles that must not move in the given direction in this solve (true: inflation).
  std::span<const std::pair<BundleId, bool>> blocked;
  // Bundles whose change is fixed to the given integer in this solve.
  std::span<const std::pair<BundleId, int64_t>> fixed;
  // A descent step over the whole subproblem (IntegerSheetPump's bulk descent): no root, every
  // bundle moves by at most one unit, priced by its exact objective change (kUnitCost), so the
  // LP's optimum is the best combination of unit moves, and a negative optimum an improvement.
  bool unit_moves = false;
  // For unit moves on parts with handles, where the flow holds the periods at zero
  // (core/isp/sheet_network.h): whether a flow that finds no descent hands the request to the LP,
  // which moves them. The pump asks it in its thorough final pass, so that a valid q from the
  // flows comes first and the descent then stops only where the LP does.
  bool confirm_stalled_flow = false;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_REQUEST_H_
