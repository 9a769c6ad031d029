// SPDX-License-Identifier: Apache-2.0
// Union-find over integer ids 0..n-1 with path halving. Joining keeps the smaller id as the
// representative, so the groups it forms number deterministically by their smallest member
// (arc bundles, subproblems and merged subproblems all rely on that order).
#ifndef ISPQ_CORE_DISJOINT_SETS_H_
#define ISPQ_CORE_DISJOINT_SETS_H_

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace ispq {

class DisjointSets {
 public:
  explicit DisjointSets(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }

  // The smallest id in x's set.
  int32_t Find(int32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void Join(int32_t x, int32_t y) {
    x = Find(x);
    y = Find(y);
    if (x != y) parent_[std::max(x, y)] = std::min(x, y);
  }

 private:
  std::vector<int32_t> parent_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_DISJOINT_SETS_H_
