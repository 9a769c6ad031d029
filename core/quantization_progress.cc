// SPDX-License-Identifier: Apache-2.0
#include "core/quantization_progress.h"

namespace ispq {

const char* QuantizationPhaseName(QuantizationPhase phase) {
  switch (phase) {
    case QuantizationPhase::kGreedy:
      return "greedy";
    case QuantizationPhase::kSeparation:
      return "separation";
    case QuantizationPhase::kFailsafe:
      return "failsafe";
    case QuantizationPhase::kFinal:
      return "final";
    case QuantizationPhase::kExact:
      return "exact";
    case QuantizationPhase::kLayers:
      return "layers";
  }
  return "unknown";
}

}  // namespace ispq
