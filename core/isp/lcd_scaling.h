// SPDX-License-Identifier: Apache-2.0
// From a rational LP solution to an integer sheet (paper section 4.3.1): the simplex returns a
// vertex with small rational entries, usually integers, occasionally halves (the T-junction U-turn
// of Fig. 6) and rarely quarters or eighths (nested U-turns, Fig. 7). Multiplying by the least
// common denominator gives an integer sheet with the same support and proportions (core/README.md,
// section From a rational vertex to an integer step).
#ifndef ISPQ_CORE_ISP_LCD_SCALING_H_
#define ISPQ_CORE_ISP_LCD_SCALING_H_

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace ispq {

// Least common denominator of `values`, each read as a fraction with a denominator of at most
// max_denominator (to within `tolerance` of a multiple of 1/denominator). nullopt when a value
// is no such fraction or the common denominator exceeds max_lcd: the solve is then rejected
// rather than turned into a huge sheet.
std::optional<int64_t> LeastCommonDenominator(std::span<const double> values,
                                              int64_t max_denominator = 64, int64_t max_lcd = 1024,
                                              double tolerance = 1e-6);

// round(lcd * v) for every value.
std::vector<int64_t> ScaleToIntegers(std::span<const double> values, int64_t lcd);

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_LCD_SCALING_H_
