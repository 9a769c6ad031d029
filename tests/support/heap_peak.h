// SPDX-License-Identifier: Apache-2.0
// The peak of live heap bytes while a piece of code runs, counted by malloc itself: for the tests
// and the benchmark that hold the server's memory estimates (server/memory/memory_estimates.h) to
// what a solve really allocates.
//
// Linking the library `ispq_heap_peak` into an executable replaces glibc's malloc family in that
// executable (glibc supports this: the replacements forward to __libc_malloc and friends), so
// every allocation of every library (protobuf, CLP, CBC, CoinUtils, the C++ runtime) is counted
// by its usable size. Unlike the resident set size this does not depend on what the allocator
// kept from earlier work or on the page size, so the same run gives the same figure every time.
// Link it only into executables that need it: each malloc and free costs two relaxed atomic
// updates more.
#ifndef ISPQ_TESTS_SUPPORT_HEAP_PEAK_H_
#define ISPQ_TESTS_SUPPORT_HEAP_PEAK_H_

#include <cstdint>

namespace ispq::testing {

// Whether the counting malloc is linked in (false: the figures below are all 0).
bool HeapCountingActive();

// Live heap bytes now (allocations counted by usable size, minus frees), since the process began.
int64_t LiveHeapBytes();

// Measures the peak of live heap bytes above the level at construction. Scopes do not nest: a
// scope restarts the process-wide peak.
class HeapPeakScope {
 public:
  HeapPeakScope();
  HeapPeakScope(const HeapPeakScope&) = delete;
  HeapPeakScope& operator=(const HeapPeakScope&) = delete;

  // The highest live heap bytes so far in this scope, minus the level at its start (>= 0).
  int64_t PeakBytes() const;

 private:
  int64_t baseline_;
};

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_HEAP_PEAK_H_
