// SPDX-License-Identifier: Apache-2.0
// The unfavorability weights of the sheet LP objective (paper eq. 3-4, App. A; core/README.md,
// section Weights).
//
// A sheet that moves an arc by one unit toward its target is cheap (tier 1, weight <= 1/2), one
// that moves it across its target costs about |A| (tier 2), and one that moves it further away
// costs at least |A|^2 (tier 3). Each tier outweighs all cheaper tiers combined, so the LP only
// pays for an unfavorable move when no combination of favorable ones can do the job.
//
// A bundle's weight is capped at kMaxSheetWeight: CLP refuses objective coefficients beyond
// 1e25, and tier 3 grows with |A|^2 times the distance to the target. The cap only merges
// weights that are already larger than any sum of tier-1 and tier-2 weights of a mesh the
// service accepts, so the order of the tiers is kept.
#ifndef ISPQ_CORE_ISP_SHEET_WEIGHTS_H_
#define ISPQ_CORE_ISP_SHEET_WEIGHTS_H_

#include <algorithm>
#include <span>

namespace ispq {

inline constexpr double kMaxSheetWeight = 1e20;

// Weight of moving one arc by one unit, given epsilon, the signed distance still to go to the
// target in the direction of the move (eq. 3: l - q when inflating, q - l when deflating).
inline double SheetWeight(double epsilon, double num_arcs) {
  if (epsilon >= 1) return 1.0 / (epsilon + 1);
  if (epsilon >= 0) return num_arcs / (epsilon + 1);
  return num_arcs * num_arcs * (1 - epsilon);
}

struct BundleWeights {
  double inflate;
  double deflate;
};

// A bundle's column weights: one bundle variable moves every arc of the bundle, so it pays the
// sum of its arcs' weights. `targets` are the scaled targets s * l_a of the bundle's arcs and
// `value` their common current length.
inline BundleWeights BundleSheetWeights(std::span<const double> targets, double value,
                                        double num_arcs) {
  BundleWeights w{0, 0};
  for (double target : targets) {
    w.inflate += SheetWeight(target - value, num_arcs);
    w.deflate += SheetWeight(value - target, num_arcs);
  }
  return {std::min(w.inflate, kMaxSheetWeight), std::min(w.deflate, kMaxSheetWeight)};
}

// Alternative weights: a bundle's exact objective change for one unit of movement, floored at a
// small positive value so the LP stays bounded. Unlike eq. 4, which only ranks moves by tier,
// these price the cheap separating sheets by what they really cost.
inline BundleWeights BundleMarginalWeights(std::span<const double> targets, double value,
                                           double floor) {
  BundleWeights w{0, 0};
  for (double target : targets) {
    w.inflate += std::max(1 - 2 * (target - value), floor);
    w.deflate += std::max(1 - 2 * (value - target), floor);
  }
  return {std::min(w.inflate, kMaxSheetWeight), std::min(w.deflate, kMaxSheetWeight)};
}

// A bundle's exact objective change for a move of one unit either way: (x + 1 - t)^2 - (x - t)^2
// = 1 - 2 (t - x) per arc up, 1 - 2 (x - t) down. Negative where the move improves; the two
// directions sum to twice the arc count, so no solution moves a bundle both ways.
inline BundleWeights BundleUnitCosts(std::span<const double> targets, double value) {
  BundleWeights w{0, 0};
  for (double target : targets) {
    w.inflate += 1 - 2 * (target - value);
    w.deflate += 1 - 2 * (value - target);
  }
  return w;
}

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_WEIGHTS_H_
