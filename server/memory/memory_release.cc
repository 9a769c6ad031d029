// SPDX-License-Identifier: Apache-2.0
#include "server/memory/memory_release.h"

#include <malloc.h>

namespace ispq::server {

void ReleaseFreedMemory() { malloc_trim(0); }

}  // namespace ispq::server
