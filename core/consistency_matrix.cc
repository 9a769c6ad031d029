// SPDX-License-Identifier: Apache-2.0
#include "core/consistency_matrix.h"

namespace ispq {

ConsistencyMatrix::ConsistencyMatrix(const TMesh& mesh) {
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    for (int i = 0; i < 4; ++i) {
      const PatchSide plus = mesh.patch_side(p, i);
      if (IsNegative(plus.dir)) continue;
      terms_.OpenList();
      for (HalfarcId h : plus.halfarcs) terms_.PushToLast({ArcOf(h), +1});
      for (int j = 0; j < 4; ++j) {
        const PatchSide minus = mesh.patch_side(p, j);
        if (minus.dir != Opposite(plus.dir)) continue;
        for (HalfarcId h : minus.halfarcs) terms_.PushToLast({ArcOf(h), -1});
      }
      info_.push_back({p, AxisOf(plus.dir)});
    }
  }
}

int64_t ConsistencyMatrix::RowValue(int r, std::span<const int64_t> q) const {
  int64_t sum = 0;
  for (const LinearTerm& t : terms_[r]) sum += t.coef * q[t.var];
  return sum;
}

}  // namespace ispq
