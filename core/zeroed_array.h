// SPDX-License-Identifier: Apache-2.0
// An array of n zero-filled values whose memory is not written when it is allocated.
//
// For large per-element tables of which a run reads a small part (core/on_demand_lists.h,
// core/separation_search_tables.h): calloc hands out fresh pages as they are, zero, so only the
// pages a run writes or reads are ever touched (a first touch costs about 12 us a page on the
// development VM). A std::vector would write every value when it is sized.
#ifndef ISPQ_CORE_ZEROED_ARRAY_H_
#define ISPQ_CORE_ZEROED_ARRAY_H_

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>

namespace ispq {

struct FreeDeleter {
  void operator()(void* p) const { std::free(p); }
};

template <typename T>
using ZeroedArray = std::unique_ptr<T[], FreeDeleter>;

// n values of T, all bytes zero. T must be a type for which that is a value (integers, and
// aggregates of them whose zero means "unset").
template <typename T>
ZeroedArray<T> MakeZeroedArray(size_t n) {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
  T* values = static_cast<T*>(std::calloc(n, sizeof(T)));
  if (values == nullptr && n > 0) throw std::bad_alloc();  // as a vector would
  return ZeroedArray<T>(values);
}

}  // namespace ispq

#endif  // ISPQ_CORE_ZEROED_ARRAY_H_
