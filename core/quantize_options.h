// What a quantization is asked to do: the scaling of the targets and the product's switches.
// The facade (core/quantizer.h) validates them; the ISP engine (core/isp/) reads them.
#ifndef ISPQ_CORE_QUANTIZE_OPTIONS_H_
#define ISPQ_CORE_QUANTIZE_OPTIONS_H_

#include <limits>

#include "core/separation_check.h"

namespace ispq {

struct QuantizeOptions {
  double scaling = 1.0;              // s: targets are s * l_a; must be finite and > 0
  bool mixed_sign = true;            // paper section 4.3.3
  bool decompose = true;             // independent subproblems (paper section 4.4)
  bool per_arc_nonnegative = false;  // add q_a >= 0 for every arc to the block-extent rows
  // The searches the result must pass (core/separation_check.h); both unless reproducing upstream.
  SeparationRule separation = SeparationRule::kBothSearches;
  double time_limit_seconds = std::numeric_limits<double>::infinity();
};

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZE_OPTIONS_H_
