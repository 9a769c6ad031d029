// SPDX-License-Identifier: Apache-2.0
#include "core/isp/lcd_scaling.h"

#include <cmath>
#include <numeric>

namespace ispq {
namespace {

bool IsMultipleOfUnit(double scaled, double tolerance) {
  return std::abs(scaled - std::round(scaled)) <= tolerance;
}

}  // namespace

std::optional<int64_t> LeastCommonDenominator(std::span<const double> values,
                                              int64_t max_denominator, int64_t max_lcd,
                                              double tolerance) {
  int64_t lcd = 1;
  for (double v : values) {
    if (!std::isfinite(v)) return std::nullopt;
    // The running lcd already clears most denominators; test it before searching.
    if (IsMultipleOfUnit(v * static_cast<double>(lcd), tolerance * static_cast<double>(lcd))) {
      continue;
    }
    int64_t denominator = 0;
    for (int64_t d = 2; d <= max_denominator; ++d) {
      if (IsMultipleOfUnit(v * static_cast<double>(d), tolerance * static_cast<double>(d))) {
        denominator = d;
        break;
      }
    }
    if (denominator == 0) return std::nullopt;
    lcd = std::lcm(lcd, denominator);
    if (lcd > max_lcd) return std::nullopt;
  }
  return lcd;
}

std::vector<int64_t> ScaleToIntegers(std::span<const double> values, int64_t lcd) {
  std::vector<int64_t> scaled(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    scaled[i] = std::llround(values[i] * static_cast<double>(lcd));
  }
  return scaled;
}

}  // namespace ispq
