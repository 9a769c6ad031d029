// SPDX-License-Identifier: Apache-2.0
#include "core/block_extents.h"

namespace ispq {
namespace {

int64_t SumOver(std::span<const ArcId> arcs, std::span<const int64_t> q) {
  int64_t sum = 0;
  for (ArcId a : arcs) sum += q[a];
  return sum;
}

}  // namespace

std::span<const ArcId> ExtentRowArcs(const TMesh& mesh, BlockId b, int axis) {
  return mesh.block_edge_arcs(b, EdgeCode(axis, true, true));
}

int64_t BlockExtent(const TMesh& mesh, BlockId b, int axis, std::span<const int64_t> q) {
  return SumOver(ExtentRowArcs(mesh, b, axis), q);
}

std::optional<int64_t> HexCount(const TMesh& mesh, std::span<const int64_t> q) {
  int64_t hexes = 0;
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    int64_t product = 1;
    for (int axis = 0; axis < 3; ++axis) {
      const int64_t extent = SumOver(mesh.block_edge_arcs(b, EdgeCode(axis, false, false)), q);
      if (__builtin_mul_overflow(product, extent, &product)) return std::nullopt;
    }
    if (__builtin_add_overflow(hexes, product, &hexes)) return std::nullopt;
  }
  return hexes;
}

double ContinuousHexVolume(const TMesh& mesh) {
  double volume = 0;
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    double product = 1;
    for (int axis = 0; axis < 3; ++axis) {
      double extent = 0;
      for (ArcId a : mesh.block_edge_arcs(b, EdgeCode(axis, false, false))) {
        extent += mesh.arc_length(a);
      }
      product *= extent;
    }
    volume += product;
  }
  return volume;
}

}  // namespace ispq
