// SPDX-License-Identifier: Apache-2.0
// Whether this build's malloc is a sanitizer's (AddressSanitizer, ThreadSanitizer): tests of
// what glibc's heap does (trimming, mapping thresholds) have nothing to observe there.
#ifndef ISPQ_TESTS_SUPPORT_SANITIZER_MALLOC_H_
#define ISPQ_TESTS_SUPPORT_SANITIZER_MALLOC_H_

namespace ispq::testing {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitizerMalloc = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitizerMalloc = true;
#else
inline constexpr bool kSanitizerMalloc = false;
#endif
#else
inline constexpr bool kSanitizerMalloc = false;
#endif

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_SANITIZER_MALLOC_H_
