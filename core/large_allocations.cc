// SPDX-License-Identifier: Apache-2.0
#include "core/large_allocations.h"

#include <malloc.h>

namespace ispq {

bool MapLargeAllocationsSeparately() {
  // Setting the threshold also turns off glibc's adjustment of it (and of the trim threshold).
  return mallopt(M_MMAP_THRESHOLD, static_cast<int>(kSeparateMappingMinBytes)) == 1;
}

}  // namespace ispq
