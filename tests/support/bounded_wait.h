// SPDX-License-Identifier: Apache-2.0
// Waiting in tests without making time a pass/fail condition.
//
// A test that waits for something (a job to end, a process to exit, a port to close, a status to
// change) bounds the wait only so that a hang fails with a message rather than at ctest's
// timeout. It never asserts that the thing happened *within* a short time: a 2-core machine
// shared with other tests and builds cannot promise that, and such a test fails for the load,
// not for the code. Assert on outcomes and counters instead; measure time in benchmarks.
#ifndef ISPQ_TESTS_SUPPORT_BOUNDED_WAIT_H_
#define ISPQ_TESTS_SUPPORT_BOUNDED_WAIT_H_

#include "absl/time/clock.h"
#include "absl/time/time.h"

namespace ispq::testing {

// Long enough that only a hang reaches it; the ctest timeout (900 s in tests/run.sh) is longer.
inline constexpr absl::Duration kSafetyNet = absl::Minutes(5);

// Polls `done()` until it holds; whether it did before `timeout`.
template <typename Predicate>
bool WaitUntil(Predicate done, absl::Duration timeout = kSafetyNet,
               absl::Duration interval = absl::Milliseconds(10)) {
  const absl::Time deadline = absl::Now() + timeout;
  while (!done()) {
    if (absl::Now() >= deadline) return false;
    absl::SleepFor(interval);
  }
  return true;
}

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_BOUNDED_WAIT_H_
