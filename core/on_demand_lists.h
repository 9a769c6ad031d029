// SPDX-License-Identifier: Apache-2.0
// A list of lists whose lists are built when first asked for, in any order.
//
// Some per-element tables are read only around the elements an algorithm visits: the separation
// search reads its mesh tables around the nodes it pops and the blocks of its fans, which on a q
// with few zero-length arcs is a small part of a large mesh (core/separation_search_tables.h).
// Building every list up front costs time and freshly touched memory for lists nobody reads;
// here each list is appended to one value array when it is built, so a list is still a span of
// one array and a value keeps its index in that array for good (values are only appended).
#ifndef ISPQ_CORE_ON_DEMAND_LISTS_H_
#define ISPQ_CORE_ON_DEMAND_LISTS_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/zeroed_array.h"

namespace ispq {

template <typename T>
class OnDemandLists {
 public:
  // `max_values` bounds the values of all lists together. Room for them is reserved at once, so
  // that building lists never copies the values built before; the room only costs memory where
  // values are written. Neither that room nor the per-list bookkeeping is written up front
  // (core/zeroed_array.h), so unread parts of a large table are never touched.
  OnDemandLists(int num_lists, size_t max_values)
      : num_lists_(num_lists), ranges_(MakeZeroedArray<Range>(static_cast<size_t>(num_lists))) {
    values_.reserve(max_values);
  }

  int size() const { return num_lists_; }
  bool built(int i) const { return ranges_[i].size_plus_one != 0; }

  // Starts list i, which must not be built yet; the values pushed until the next Open are its.
  void Open(int i) {
    ranges_[i] = {static_cast<uint32_t>(values_.size()), 1};
    open_ = i;
  }
  void Push(const T& value) {
    values_.push_back(value);
    ++ranges_[open_].size_plus_one;
  }

  // List i, which must be built. The span is valid until the next Push.
  std::span<const T> operator[](int i) const {
    const Range& r = ranges_[i];
    return {values_.data() + r.begin, r.size_plus_one - 1};
  }
  // Where list i (built) starts among all values: value(first_index(i) + k) is its k-th value
  // for good, also after later lists were pushed.
  int32_t first_index(int i) const { return static_cast<int32_t>(ranges_[i].begin); }
  const T& value(int32_t index) const { return values_[index]; }
  // Values of all built lists.
  size_t num_values() const { return values_.size(); }

 private:
  // 0 in size_plus_one: not built yet.
  struct Range {
    uint32_t begin;
    uint32_t size_plus_one;
  };
  int num_lists_;
  ZeroedArray<Range> ranges_;
  std::vector<T> values_;
  int open_ = -1;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ON_DEMAND_LISTS_H_
