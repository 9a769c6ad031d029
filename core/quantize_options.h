// SPDX-License-Identifier: Apache-2.0
// What a quantization is asked to do: the scaling of the targets, the method and the product's
// switches. The facade (core/quantizer.h) validates them; the ISP engine (core/isp/) and the
// exact mode (core/exact/) read them.
#ifndef ISPQ_CORE_QUANTIZE_OPTIONS_H_
#define ISPQ_CORE_QUANTIZE_OPTIONS_H_

#include <cstdint>
#include <limits>

#include "core/separation_check.h"

namespace ispq {

enum class QuantizationMethod : uint8_t {
  kIsp,    // the Integer-Sheet-Pump alone (the product's default)
  kExact,  // ISP, then the MILP with the lazy separation loop until optimality is proven
};

// Whether a result carries a lower bound (core/exact/lower_bound.h). Exact mode always has one.
enum class LowerBoundMode : uint8_t {
  kAuto,  // for meshes of at most kAutoLowerBoundMaxArcs arcs
  kAlways,
  kNever,
};

// The ISP bound's LP grows with the mesh while ISP itself stays fast; up to this size its cost is
// small next to ISP's (README, "Quality and speed").
inline constexpr int kAutoLowerBoundMaxArcs = 5000;

// Exact mode without a time limit stops after this long, returning the best q and its gap.
inline constexpr double kDefaultExactTimeLimitSeconds = 60;

struct QuantizeOptions {
  double scaling = 1.0;              // s: targets are s * l_a; must be finite and > 0
  bool mixed_sign = true;            // paper section 4.3.3
  bool decompose = true;             // independent subproblems (paper section 4.4)
  bool per_arc_nonnegative = false;  // add q_a >= 0 for every arc to the block-extent rows
  // The searches the result must pass (core/separation_check.h); both unless reproducing upstream.
  SeparationRule separation = SeparationRule::kBothSearches;
  double time_limit_seconds = std::numeric_limits<double>::infinity();
  QuantizationMethod method = QuantizationMethod::kIsp;
  LowerBoundMode lower_bound = LowerBoundMode::kAuto;
};

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZE_OPTIONS_H_
