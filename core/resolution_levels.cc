// SPDX-License-Identifier: Apache-2.0
#include "core/resolution_levels.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ispq {

bool IsLevelPercent(int percent) {
  return std::find(kLevelPercents.begin(), kLevelPercents.end(), percent) != kLevelPercents.end();
}

std::optional<double> ScalingForPercent(std::span<const double> lengths, int percent) {
  if (lengths.empty() || percent < 0 || percent > 100) return std::nullopt;
  std::vector<double> sorted(lengths.begin(), lengths.end());
  std::sort(sorted.begin(), sorted.end());
  const size_t n = sorted.size();
  // std::round rounds half away from zero, as the format requires.
  const size_t k = static_cast<size_t>(std::round(percent * static_cast<double>(n) / 100.0));
  if (k < n) return 0.5 / sorted[k];
  return 0.999 * 0.5 / sorted[n - 1];
}

}  // namespace ispq
