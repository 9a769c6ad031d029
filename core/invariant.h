// SPDX-License-Identifier: Apache-2.0
// Checks of what the code relies on and only a bug can break: a factorized basis that matches
// the variables' statuses, a quantization with one non-negative length per arc, a job that ends
// once. Bad input never reaches one of these (it is refused with a status that names it); a
// failed check means the program's own state can no longer be trusted, so it prints where and
// what, and aborts, leaving the stack to the debugger or the sanitizer's report.
//
//   ISPQ_INVARIANT(condition, explanation)  checked in the debug and sanitizer builds (CMake
//       option ISPQ_INVARIANTS, on in the debug, asan, tsan and fuzz presets); in release builds
//       the condition is compiled but never evaluated, so a check may cost what it needs to.
//   ISPQ_RELEASE_INVARIANT(condition, explanation)  checked in every build: for cheap checks
//       whose failure would otherwise read or write outside an array.
//
// `if constexpr (kCheckInvariants)` guards a check that needs a loop.
#ifndef ISPQ_CORE_INVARIANT_H_
#define ISPQ_CORE_INVARIANT_H_

#include <cstdio>
#include <cstdlib>

namespace ispq {

#ifdef ISPQ_CHECK_INVARIANTS
inline constexpr bool kCheckInvariants = true;
#else
inline constexpr bool kCheckInvariants = false;
#endif

[[noreturn]] inline void InvariantFailed(const char* file, int line, const char* condition,
                                         const char* explanation) {
  std::fprintf(stderr, "%s:%d: invariant failed: %s (%s)\n", file, line, condition, explanation);
  std::fflush(stderr);
  std::abort();
}

}  // namespace ispq

#define ISPQ_RELEASE_INVARIANT(condition, explanation)                      \
  do {                                                                      \
    if (!(condition)) {                                                     \
      ::ispq::InvariantFailed(__FILE__, __LINE__, #condition, explanation); \
    }                                                                       \
  } while (false)

#define ISPQ_INVARIANT(condition, explanation)                              \
  do {                                                                      \
    if (::ispq::kCheckInvariants && !(condition)) {                         \
      ::ispq::InvariantFailed(__FILE__, __LINE__, #condition, explanation); \
    }                                                                       \
  } while (false)

#endif  // ISPQ_CORE_INVARIANT_H_
