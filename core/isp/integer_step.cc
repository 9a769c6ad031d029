// SPDX-License-Identifier: Apache-2.0
#include "core/isp/integer_step.h"

#include <algorithm>
#include <cmath>

namespace ispq {

int64_t OptimalIntegerStep(double a, double b, int64_t t_min, int64_t t_max) {
  const double vertex = -b / (2 * a);
  // Clamp in floating point first so that rounding a huge vertex cannot overflow.
  const double clamped = std::clamp(vertex, static_cast<double>(t_min), static_cast<double>(t_max));
  return std::clamp<int64_t>(std::llround(clamped), t_min, t_max);
}

}  // namespace ispq
