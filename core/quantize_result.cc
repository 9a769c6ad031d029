// SPDX-License-Identifier: Apache-2.0
#include "core/quantize_result.h"

namespace ispq {

const char* TerminationName(Termination termination) {
  switch (termination) {
    case Termination::kConverged:
      return "converged";
    case Termination::kTimeLimit:
      return "time_limit";
    case Termination::kInterrupted:
      return "interrupted";
    case Termination::kOptimal:
      return "optimal";
  }
  return "unknown";
}

}  // namespace ispq
