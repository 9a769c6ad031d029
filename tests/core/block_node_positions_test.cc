// SPDX-License-Identifier: Apache-2.0
#include "core/block_node_positions.h"

#include <string>
#include <vector>

#include "core/block_extents.h"
#include "gtest/gtest.h"
#include "tests/support/consistent_quantizations.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::ConsistentQuantizations;
using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::RealTMeshPath;
using ::ispq::testing::ShortName;

TEST(BlockNodePositionsTest, CubeCorners) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const BlockNodeSlots slots(cube);
  ASSERT_EQ(slots.num_slots(), 8);
  // Extents 2, 3, 5 along u, v, w.
  std::vector<int64_t> q(12);
  const int64_t extent[3] = {2, 3, 5};
  for (int edge = 0; edge < kNumEdges; ++edge) {
    for (ArcId a : cube.block_edge_arcs(0, edge)) q[a] = extent[EdgeAxis(edge)];
  }
  std::vector<IntVec3> positions(slots.num_slots());
  slots.ComputePositions(q, positions);
  for (int corner = 0; corner < kNumCorners; ++corner) {
    const SlotId s = slots.corner_slot(0, corner);
    EXPECT_EQ(slots.block_of(s), 0);
    EXPECT_EQ(slots.node_of(s), cube.block_corner(0, corner));
    EXPECT_EQ(slots.Find(0, cube.block_corner(0, corner)), s);
    const IntVec3 expected = {corner & 1 ? 2 : 0, corner & 2 ? 3 : 0, corner & 4 ? 5 : 0};
    EXPECT_EQ(positions[s], expected) << "corner " << corner;
  }
}

// For a consistent q every boundary arc of every block spans q_a along its direction, whatever
// the spanning tree, and the corners give the block extents.
TEST(BlockNodePositionsTest, RealMeshesArePathIndependent) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    const BlockNodeSlots slots(mesh);
    const std::vector<int64_t> q = ConsistentQuantizations(mesh).NearTargets(3.0);
    std::vector<IntVec3> positions(slots.num_slots());
    slots.ComputePositions(q, positions);
    for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
      for (const BlockArc& ba : mesh.block_arcs(b)) {
        const SlotId from = slots.Find(b, mesh.arc_from(ba.arc));
        const SlotId to = slots.Find(b, mesh.arc_to(ba.arc));
        ASSERT_NE(from, kNoId);
        ASSERT_NE(to, kNoId);
        EXPECT_EQ(positions[to], AddAlong(positions[from], ba.dir, q[ba.arc]));
      }
      const IntVec3 diagonal = Subtract(positions[slots.corner_slot(b, kMaxCorner)],
                                        positions[slots.corner_slot(b, kMinCorner)]);
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_EQ(diagonal[axis], BlockExtent(mesh, b, axis, q));
      }
      EXPECT_EQ(positions[slots.corner_slot(b, kMinCorner)], (IntVec3{0, 0, 0}));
    }
    // A node that is not on a block's boundary has no slot there.
    for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
      const std::span<const BlockId> on = mesh.node_blocks(n);
      for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
        const bool listed = std::find(on.begin(), on.end(), b) != on.end();
        EXPECT_EQ(slots.Find(b, n) != kNoId, listed);
      }
    }
  }
}

// One block's positions are those of the whole computation, and the other slots are left as they
// were.
TEST(BlockNodePositionsTest, OneBlockAtATime) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (size_t i = 0; i < files.size(); i += 4) {
    SCOPED_TRACE(ShortName(files[i]));
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const BlockNodeSlots slots(mesh);
    const std::vector<int64_t> q = ConsistentQuantizations(mesh).NearTargets(3.0);
    std::vector<IntVec3> all(slots.num_slots());
    slots.ComputePositions(q, all);
    const IntVec3 untouched = {-7, -7, -7};
    for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
      std::vector<IntVec3> one(slots.num_slots(), untouched);
      slots.ComputeBlockPositions(b, q, one);
      for (SlotId s = 0; s < slots.num_slots(); ++s) {
        EXPECT_EQ(one[s], slots.block_of(s) == b ? all[s] : untouched) << "block " << b;
      }
    }
  }
}

}  // namespace
}  // namespace ispq
