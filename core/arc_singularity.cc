// SPDX-License-Identifier: Apache-2.0
#include "core/arc_singularity.h"

#include "core/direction.h"

namespace ispq {

std::vector<int> QuarterTurnsAroundArcs(const TMesh& mesh) {
  // Every block around an arc counts two quarter turns, minus one where the arc is an edge.
  std::vector<int> turns(mesh.num_arcs(), 0);
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    turns[a] = 2 * static_cast<int>(mesh.arc_blocks(a).size());
  }
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int edge = 0; edge < kNumEdges; ++edge) {
      for (ArcId a : mesh.block_edge_arcs(b, edge)) --turns[a];
    }
  }
  return turns;
}

bool ArcOnBoundary(const TMesh& mesh, ArcId a) {
  for (HalfpatchId hp : mesh.arc_halfpatches(a)) {
    if (mesh.patch_boundary(PatchOf(hp))) return true;
  }
  return false;
}

}  // namespace ispq
