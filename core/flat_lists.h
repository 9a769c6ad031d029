// SPDX-License-Identifier: Apache-2.0
// A list of lists stored in two flat arrays (compressed sparse rows).
//
// The T-mesh's adjacency (node -> halfarcs, patch -> cycle, block -> patches, ...) is a list of
// short lists per element. Storing them as one value array plus offsets keeps each mesh a
// handful of allocations and makes iteration cache-friendly; list i is a std::span.
#ifndef ISPQ_CORE_FLAT_LISTS_H_
#define ISPQ_CORE_FLAT_LISTS_H_

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace ispq {

template <typename T>
class FlatLists {
 public:
  FlatLists() : offsets_{0} {}

  // Appends one list at the end.
  template <typename Range>
  void Append(const Range& values) {
    for (const auto& v : values) values_.push_back(v);
    offsets_.push_back(static_cast<uint32_t>(values_.size()));
  }
  // Appends an element to the last list (opened with OpenList).
  void OpenList() { offsets_.push_back(static_cast<uint32_t>(values_.size())); }
  void PushToLast(const T& v) {
    values_.push_back(v);
    ++offsets_.back();
  }

  int size() const { return static_cast<int>(offsets_.size()) - 1; }
  std::span<const T> operator[](int i) const {
    return {values_.data() + offsets_[i], values_.data() + offsets_[i + 1]};
  }

 private:
  std::vector<T> values_;
  std::vector<uint32_t> offsets_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_FLAT_LISTS_H_
