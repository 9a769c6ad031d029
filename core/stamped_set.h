// SPDX-License-Identifier: Apache-2.0
// A set over dense integer ids that is emptied in O(1).
//
// The separation search runs hundreds of short searches per call, each with its own visited
// sets over all nodes (and a fan set over all blocks per expanded walk). Clearing an O(|N|)
// array each time would dominate; instead every member is stamped with the current generation
// and clearing bumps the generation. The array is only rewritten when the counter wraps.
#ifndef ISPQ_CORE_STAMPED_SET_H_
#define ISPQ_CORE_STAMPED_SET_H_

#include <algorithm>
#include <cstdint>
#include <vector>

namespace ispq {

class StampedSet {
 public:
  // Makes room for ids 0..size-1 and empties the set.
  void Resize(int size) {
    stamps_.assign(size, 0);
    generation_ = 1;
  }
  void Clear() {
    if (++generation_ == 0) {
      std::fill(stamps_.begin(), stamps_.end(), 0);
      generation_ = 1;
    }
  }
  bool Contains(int id) const { return stamps_[id] == generation_; }
  void Insert(int id) { stamps_[id] = generation_; }

 private:
  std::vector<uint32_t> stamps_;
  uint32_t generation_ = 1;
};

}  // namespace ispq

#endif  // ISPQ_CORE_STAMPED_SET_H_
