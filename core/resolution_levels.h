// SPDX-License-Identifier: Apache-2.0
// The resolution levels (proto/README.md, section Resolution levels and scaling): a scaling factor
// s per percentage p such that roughly p percent of the arcs get a scaled target length s * l
// below 1/2.
#ifndef ISPQ_CORE_RESOLUTION_LEVELS_H_
#define ISPQ_CORE_RESOLUTION_LEVELS_H_

#include <array>
#include <optional>
#include <span>

namespace ispq {

// The 8 percentages the format defines, in file order.
inline constexpr std::array<int, 8> kLevelPercents = {0, 1, 5, 10, 17, 25, 50, 100};

bool IsLevelPercent(int percent);

// s for level `percent` over the unscaled arc lengths (any order, all > 0). nullopt if `lengths`
// is empty or percent is outside 0..100.
std::optional<double> ScalingForPercent(std::span<const double> lengths, int percent);

}  // namespace ispq

#endif  // ISPQ_CORE_RESOLUTION_LEVELS_H_
