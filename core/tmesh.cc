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

HalfarcId TMesh::HalfpatchCycleAt(HalfpatchId hp, int i) const {
  const std::span<const HalfarcId> cycle = patch_cycle_[hp >> 1];
  if ((hp & 1) == 0) return cycle[i];
  return Twin(cycle[cycle.size() - 1 - i]);
}

}  // namespace ispq
