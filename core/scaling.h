// SPDX-License-Identifier: Apache-2.0
// The scaling factor s of a quantization (the target length of arc a is s * l_a), as a caller
// chooses it: s itself, one of the resolution levels, or the hex count the continuous blocks
// should have (proto/README.md, section Resolution levels and scaling). Resolving the choice
// against a mesh is domain logic that the CLI, the service and the validator share; the API's
// Scaling message only translates into a ScalingChoice (core/proto/quantization_proto.h).
#ifndef ISPQ_CORE_SCALING_H_
#define ISPQ_CORE_SCALING_H_

#include <cstdint>

#include "absl/status/statusor.h"
#include "core/tmesh.h"

namespace ispq {

struct ScalingChoice {
  enum class Kind : uint8_t { kUnset, kFactor, kLevelPercent, kTargetHexes };

  static ScalingChoice Factor(double s) { return {.kind = Kind::kFactor, .factor = s}; }
  static ScalingChoice LevelPercent(int p) { return {.kind = Kind::kLevelPercent, .percent = p}; }
  static ScalingChoice TargetHexes(int64_t n) {
    return {.kind = Kind::kTargetHexes, .target_hexes = n};
  }

  Kind kind = Kind::kUnset;
  double factor = 0;         // kFactor
  int percent = 0;           // kLevelPercent
  int64_t target_hexes = 0;  // kTargetHexes
};

// s for `choice` on `mesh`. INVALID_ARGUMENT if nothing is chosen, or the factor is not positive
// and finite, the percent not one of the format's levels, or the hex count not positive.
absl::StatusOr<double> ResolveScaling(const ScalingChoice& choice, const TMesh& mesh);

}  // namespace ispq

#endif  // ISPQ_CORE_SCALING_H_
