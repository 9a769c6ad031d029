// SPDX-License-Identifier: Apache-2.0
#include "core/halfarc_neighborhood.h"

#include <algorithm>

namespace ispq {

std::vector<HalfpatchId> HalfpatchesAroundHalfarc(const TMesh& mesh, HalfarcId h) {
  const std::span<const HalfpatchId> listed = mesh.arc_halfpatches(ArcOf(h));
  std::vector<HalfpatchId> result(listed.begin(), listed.end());
  if (h & 1) {
    std::reverse(result.begin(), result.end());
    for (HalfpatchId& hp : result) hp ^= 1;
  }
  return result;
}

std::vector<BlockId> BlocksAroundHalfarc(const TMesh& mesh, HalfarcId h) {
  std::vector<BlockId> blocks;
  BlocksAroundHalfarc(mesh, h, &blocks);
  return blocks;
}

void BlocksAroundHalfarc(const TMesh& mesh, HalfarcId h, std::vector<BlockId>* blocks) {
  blocks->clear();
  // The radial order of HalfpatchesAroundHalfarc, read in place.
  const std::span<const HalfpatchId> listed = mesh.arc_halfpatches(ArcOf(h));
  const int n = static_cast<int>(listed.size());
  for (int i = 0; i < n; ++i) {
    const HalfpatchId hp = (h & 1) ? listed[n - 1 - i] ^ 1 : listed[i];
    const BlockId b = mesh.halfpatch_block(hp);
    if (b != kNoId && std::find(blocks->begin(), blocks->end(), b) == blocks->end()) {
      blocks->push_back(b);
    }
  }
}

int IndexInHalfpatchCycle(const TMesh& mesh, HalfpatchId hp, HalfarcId h) {
  const int size = mesh.halfpatch_cycle_size(hp);
  for (int i = 0; i < size; ++i) {
    if (mesh.HalfpatchCycleAt(hp, i) == h) return i;
  }
  return -1;
}

HalfarcId NextInHalfpatch(const TMesh& mesh, HalfpatchId hp, HalfarcId h) {
  const int size = mesh.halfpatch_cycle_size(hp);
  return mesh.HalfpatchCycleAt(hp, (IndexInHalfpatchCycle(mesh, hp, h) + 1) % size);
}

HalfarcId PrevInHalfpatch(const TMesh& mesh, HalfpatchId hp, HalfarcId h) {
  const int size = mesh.halfpatch_cycle_size(hp);
  return mesh.HalfpatchCycleAt(hp, (IndexInHalfpatchCycle(mesh, hp, h) + size - 1) % size);
}

BlockId FrameBlockOfHalfpatch(const TMesh& mesh, HalfpatchId hp) {
  const BlockId own = mesh.halfpatch_block(hp);
  return own != kNoId ? own : mesh.halfpatch_block(hp ^ 1);
}

}  // namespace ispq
