// SPDX-License-Identifier: Apache-2.0
#include "server/job_memory.h"

namespace ispq::server {

int64_t RetainedJobBytes(const v1::QuantizationResult* result) {
  // The terminal event keeps the result; ToProto copies are transient and budgeted as responses.
  return kJobOverheadBytes +
         (result != nullptr ? static_cast<int64_t>(result->SpaceUsedLong()) : 0);
}

}  // namespace ispq::server
