// SPDX-License-Identifier: Apache-2.0
// The calling process's own memory counters from /proc/self/status, for the benchmarks that
// report resident memory (tests/bench): VmRSS now, VmHWM the peak since start or the last reset.
#ifndef ISPQ_TESTS_SUPPORT_OWN_MEMORY_H_
#define ISPQ_TESTS_SUPPORT_OWN_MEMORY_H_

namespace ispq::testing {

// The value of `field` (such as "VmHWM:", colon included) in KiB; 0 if it is not there.
double OwnStatusKib(const char* field);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_OWN_MEMORY_H_
