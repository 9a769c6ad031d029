// SPDX-License-Identifier: Apache-2.0
#include "core/tmesh.h"

#include <algorithm>

namespace ispq {

std::optional<Dir> TMesh::HalfarcDirInBlock(HalfarcId h, BlockId b) const {
  const std::span<const BlockArc> arcs = block_arcs_[b];
  const ArcId a = ArcOf(h);
  const auto it = std::lower_bound(arcs.begin(), arcs.end(), a,
                                   [](const BlockArc& entry, ArcId id) { return entry.arc < id; });
  if (it == arcs.end() || it->arc != a) return std::nullopt;
  return (h & 1) ? Opposite(it->dir) : it->dir;
}

}  // namespace ispq
