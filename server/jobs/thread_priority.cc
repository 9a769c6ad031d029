// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/thread_priority.h"

#include <sys/resource.h>
#include <unistd.h>

namespace ispq::server {
namespace {

constexpr int kBackgroundNiceness = 10;

}  // namespace

void LowerCurrentThreadPriority() {
  // On Linux, PRIO_PROCESS with a thread id sets that thread's niceness alone.
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kBackgroundNiceness);
}

}  // namespace ispq::server
