// SPDX-License-Identifier: Apache-2.0
#include "core/scaling.h"

#include <cmath>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/block_extents.h"
#include "core/resolution_levels.h"

namespace ispq {

absl::StatusOr<double> ResolveScaling(const ScalingChoice& choice, const TMesh& mesh) {
  switch (choice.kind) {
    case ScalingChoice::Kind::kFactor:
      if (!std::isfinite(choice.factor) || choice.factor <= 0) {
        return absl::InvalidArgumentError(
            absl::StrCat("scaling factor ", choice.factor, " is not a positive finite number"));
      }
      return choice.factor;
    case ScalingChoice::Kind::kLevelPercent:
      if (!IsLevelPercent(choice.percent)) {
        return absl::InvalidArgumentError(
            absl::StrCat("level ", choice.percent, " is not one of 0, 1, 5, 10, 17, 25, 50, 100"));
      }
      return *ScalingForPercent(mesh.arc_lengths(), choice.percent);
    case ScalingChoice::Kind::kTargetHexes:
      if (choice.target_hexes <= 0) {
        return absl::InvalidArgumentError(
            absl::StrCat("target hex count ", choice.target_hexes, " is not positive"));
      }
      // The continuous hex count grows with s^3.
      return std::cbrt(static_cast<double>(choice.target_hexes) / ContinuousHexVolume(mesh));
    case ScalingChoice::Kind::kUnset:
      break;
  }
  return absl::InvalidArgumentError(
      "no scaling given: set a factor, a level percent or a target hex count");
}

}  // namespace ispq
