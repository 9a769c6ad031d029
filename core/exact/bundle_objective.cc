// SPDX-License-Identifier: Apache-2.0
#include "core/exact/bundle_objective.h"

#include <algorithm>
#include <cmath>

#include "core/quantization_limits.h"

namespace ispq {

BundleObjectives::BundleObjectives(const TMesh& mesh, const ArcBundles& bundles, double scaling) {
  std::vector<double> targets;
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    targets.clear();
    for (ArcId a : bundles.arcs(b)) targets.push_back(scaling * mesh.arc_length(a));
    targets_.Append(targets);
    double sum = 0;
    for (double t : targets) sum += t;
    mean_.push_back(sum / static_cast<double>(targets.size()));
    best_.push_back(std::llround(mean_.back()));
    minimum_sum_ += Value(b, best_.back());
  }
}

double BundleObjectives::Value(BundleId b, int64_t x) const {
  const double xd = static_cast<double>(x);
  double sum = 0;
  for (double t : targets_[b]) sum += (xd - t) * (xd - t);
  return sum;
}

IntegerWindow BundleObjectives::Window(BundleId b, double slack) const {
  // f_b(x) = m (x - mean)^2 + const, so the window is |x - mean| <= r with
  // m r^2 = m (best - mean)^2 + slack.
  const double m = static_cast<double>(targets_[b].size());
  const double offset = static_cast<double>(best_[b]) - mean_[b];
  const double r = std::sqrt(offset * offset + std::max(0.0, slack) / m);
  const double margin = 1e-7 * (1 + std::abs(mean_[b]) + r);
  const double limit = static_cast<double>(kMaxArcLength);
  IntegerWindow window;
  window.lo = static_cast<int64_t>(std::ceil(std::max(-limit, mean_[b] - r - margin)));
  window.hi = static_cast<int64_t>(std::floor(std::min(limit, mean_[b] + r + margin)));
  window.lo = std::min(window.lo, best_[b]);
  window.hi = std::max(window.hi, best_[b]);
  return window;
}

Secant BundleObjectives::SecantAt(BundleId b, int64_t k) const {
  const double value = Value(b, k);
  return {k, value, Value(b, k + 1) - value};
}

double BundleObjectives::Objective(std::span<const int64_t> bundle_values) const {
  double sum = 0;
  for (BundleId b = 0; b < num_bundles(); ++b) sum += Value(b, bundle_values[b]);
  return sum;
}

}  // namespace ispq
