// SPDX-License-Identifier: Apache-2.0
// The frame rules on small grid meshes: every built mesh passes; block edges that are not chains
// from corner to corner along their axis are named, in the order the source listed the edges;
// patches that leave their face or whose sides run along other directions are named; and node
// coordinates that disagree with an arc's length are refused within a tolerance relative to the
// coordinates. The edge lists are an argument and are edited directly; the other cases are grid
// messages with one field edited, loaded through TMeshFromProto, since a TMesh that breaks these
// rules cannot exist (the real-file table in tests/core/proto/tmesh_from_proto_test.cc covers
// cycles facing away, transitions and shifted coordinates on a real mesh).
#include "core/tmesh_frame_checks.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/proto/tmesh_from_proto.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using testing::GridTMesh;
using testing::GridTMeshSpec;
using ::testing::HasSubstr;

// Block 0 is [0,2] x [0,1] x [0,1]; blocks 1 and 2 sit on its POS_W face, one per half in u,
// so that its u-edges on that face are chains of two arcs and the face has two patches.
GridTMeshSpec TJunction() {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {2, 1, 1}}, {{0, 0, 1}, {1, 1, 2}}, {{1, 0, 1}, {2, 1, 2}}};
  return spec;
}

// What the builder hands CheckBlockEdgeChains: per block and edge code, the edge's halfarcs
// along its positive axis.
FlatLists<HalfarcId> EdgeHalfarcs(const TMesh& mesh) {
  FlatLists<HalfarcId> lists;
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int e = 0; e < kNumEdges; ++e) {
      std::vector<HalfarcId> halfarcs;
      for (ArcId a : mesh.block_edge_arcs(b, e)) {
        halfarcs.push_back(
            mesh.HalfarcDirInBlock(2 * a, b) == MakeDir(EdgeAxis(e), false) ? 2 * a : 2 * a + 1);
      }
      lists.Append(halfarcs);
    }
  }
  return lists;
}

std::vector<int8_t> InCodeOrder(const TMesh& mesh) {
  std::vector<int8_t> order;
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int e = 0; e < kNumEdges; ++e) order.push_back(static_cast<int8_t>(e));
  }
  return order;
}

// `lists` with list `index` replaced.
FlatLists<HalfarcId> Replaced(const FlatLists<HalfarcId>& lists, int index,
                              const std::vector<HalfarcId>& replacement) {
  FlatLists<HalfarcId> out;
  for (int i = 0; i < lists.size(); ++i) {
    if (i == index) {
      out.Append(replacement);
    } else {
      out.Append(lists[i]);
    }
  }
  return out;
}

std::string LoadError(const v1::TMesh& proto, const TMeshValidationOptions& options = {}) {
  const absl::StatusOr<TMesh> mesh = TMeshFromProto(proto, options);
  EXPECT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  return std::string(mesh.status().message());
}

TEST(TMeshFrameChecksTest, BuiltMeshesPass) {
  GridTMeshSpec rotated = TJunction();
  rotated.block_rotations = {{0, 9}, {2, 17}};
  for (const GridTMeshSpec& spec : {TJunction(), rotated}) {
    const TMesh mesh = testing::TMeshOrDie(testing::BuildGridTMeshOrDie(spec).proto());
    EXPECT_TRUE(CheckPatchFrames(mesh).ok());
    EXPECT_TRUE(CheckBlockEdgeChains(mesh, EdgeHalfarcs(mesh), InCodeOrder(mesh)).ok());
    EXPECT_TRUE(CheckBlockCoordinates(mesh, 1e-9).ok());
  }
}

TEST(TMeshFrameChecksTest, AnEdgeRunningBackwardsOrStoppingShortIsNamed) {
  const TMesh mesh = testing::TMeshOrDie(testing::BuildGridTMeshOrDie(TJunction()).proto());
  const FlatLists<HalfarcId> edges = EdgeHalfarcs(mesh);
  const std::vector<int8_t> order = InCodeOrder(mesh);
  // Edge codes 0..3 run along u; block 0's are chains of two arcs on the POS_W face.
  int split = -1;
  for (int e = 0; e < 4; ++e) {
    if (edges[e].size() == 2) split = e;
  }
  ASSERT_NE(split, -1);
  const std::vector<HalfarcId> chain(edges[split].begin(), edges[split].end());

  const std::vector<HalfarcId> backwards = {chain[0], chain[1] ^ 1};
  EXPECT_EQ(CheckBlockEdgeChains(mesh, Replaced(edges, split, backwards), order).message(),
            absl::StrCat("block 0: edge ", EdgeName(split),
                         " is not a chain along its positive axis (at arc ", chain[1] >> 1, ")"));

  const std::vector<HalfarcId> half = {chain[0]};
  EXPECT_EQ(CheckBlockEdgeChains(mesh, Replaced(edges, split, half), order).message(),
            absl::StrCat("block 0: edge ", EdgeName(split), " does not end at its corner node ",
                         mesh.head(chain[1])));
}

// With two broken edges, the one the source listed first is reported.
TEST(TMeshFrameChecksTest, EdgesAreCheckedInTheSourcesOrder) {
  const TMesh mesh = testing::TMeshOrDie(testing::BuildGridTMeshOrDie(TJunction()).proto());
  const FlatLists<HalfarcId> edges = EdgeHalfarcs(mesh);
  constexpr int kU = 0, kW = 8;  // an edge along u and one along w, both of block 0
  const std::vector<HalfarcId> u_reversed = {edges[kU].back() ^ 1};
  const std::vector<HalfarcId> w_reversed = {edges[kW][0] ^ 1};
  const FlatLists<HalfarcId> broken = Replaced(Replaced(edges, kU, u_reversed), kW, w_reversed);
  std::vector<int8_t> order = InCodeOrder(mesh);
  EXPECT_THAT(std::string(CheckBlockEdgeChains(mesh, broken, order).message()),
              HasSubstr("block 0: edge " + EdgeName(kU)));
  std::reverse(order.begin(), order.begin() + kNumEdges);
  EXPECT_THAT(std::string(CheckBlockEdgeChains(mesh, broken, order).message()),
              HasSubstr("block 0: edge " + EdgeName(kW)));
}

TEST(TMeshFrameChecksTest, ACycleArcMissingFromABlockIsNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(TJunction());
  const int a = grid.ArcBetween({0, 0, 1}, {0, 1, 1});  // on block 0's POS_W face
  v1::TMesh proto = grid.proto();
  for (v1::DirectedArcs& entry : *proto.mutable_blocks(0)->mutable_arcs_by_dir()) {
    auto* arcs = entry.mutable_arcs();
    const auto it = std::find(arcs->begin(), arcs->end(), a);
    if (it != arcs->end()) arcs->erase(it);
  }
  // The first patch (in id order) with that arc on its cycle and block 0 on a side.
  int first = -1;
  for (int p = 0; p < proto.patches_size() && first == -1; ++p) {
    const v1::Patch& patch = proto.patches(p);
    const bool on_block_0 = patch.blocks(0) == 0 || patch.blocks(1) == 0;
    for (int32_t h : patch.halfarcs()) {
      if (on_block_0 && h >> 1 == a) first = p;
    }
  }
  ASSERT_NE(first, -1);
  EXPECT_EQ(LoadError(proto),
            absl::StrCat("patch ", first, ": arc ", a, " of its cycle is not on block 0"));
}

// A patch moved, in its own sides and in its block's face lists, to a face its arcs cross.
TEST(TMeshFrameChecksTest, APatchOnAFaceItsArcsCrossIsNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(TJunction());
  const int p = grid.PatchAt({{0, 0, 1}, {1, 1, 1}});
  ASSERT_NE(p, -1);
  v1::TMesh proto = grid.proto();
  v1::Patch& patch = *proto.mutable_patches(p);
  const int k = patch.blocks(0) == 0 ? 0 : 1;
  ASSERT_EQ(patch.blocks(k), 0);
  ASSERT_EQ(patch.sides(k), v1::POS_W);
  patch.set_sides(k, v1::POS_U);
  for (v1::Face& face : *proto.mutable_blocks(0)->mutable_faces()) {
    auto* patches = face.mutable_patches();
    if (face.side() == v1::POS_W) {
      patches->erase(std::find(patches->begin(), patches->end(), p));
    } else if (face.side() == v1::POS_U) {
      patches->Add(p);
    }
  }
  EXPECT_THAT(LoadError(proto), HasSubstr(absl::StrCat("patch ", p, ": arc ")));
  EXPECT_THAT(LoadError(proto), HasSubstr(" runs across face POS_U of block 0"));
}

// Two adjacent sides with their directions exchanged: still two opposite pairs of equal
// lengths (the patch is a unit square), but each runs along the other's direction.
TEST(TMeshFrameChecksTest, ASideRunningAlongAnotherDirectionIsNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(TJunction());
  const int p = grid.PatchAt({{0, 0, 0}, {0, 1, 1}});
  v1::TMesh proto = grid.proto();
  auto* sides = proto.mutable_patches(p)->mutable_halfarcs_by_dir();
  const int other = 1;
  const std::string message_prefix = absl::StrCat("patch ", p, ": halfarc ");
  const v1::UVWDir first = sides->Get(0).dir();
  sides->Mutable(0)->set_dir(sides->Get(other).dir());
  sides->Mutable(other)->set_dir(first);
  const std::string message = LoadError(proto);
  EXPECT_THAT(message, HasSubstr(message_prefix));
  EXPECT_THAT(message, HasSubstr(" does not run along "));
  EXPECT_THAT(message, HasSubstr(" in block 0"));
}

TEST(TMeshFrameChecksTest, NodeCoordinatesMustMatchArcLengthsUpToARelativeTolerance) {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  spec.spacing = {{{1000.0}, {1000.0}, {1000.0}}};  // coordinates up to 1000
  const GridTMesh grid = testing::BuildGridTMeshOrDie(spec);
  const TMeshValidationOptions tight{.length_tolerance = 1e-6};
  // 1e-4 off at a coordinate of 1000: 1e-7 relative, inside the tolerance (absolute 1e-3).
  const auto shifted = [&grid](double by) {
    v1::TMesh proto = grid.proto();
    auto* uvw = proto.mutable_blocks(0)->mutable_node_uvw(0)->mutable_uvw();
    uvw->Set(0, uvw->Get(0) + by);
    return proto;
  };
  EXPECT_TRUE(TMeshFromProto(shifted(1e-4), tight).ok());
  const std::string message = LoadError(shifted(1e-2), tight);
  EXPECT_THAT(message, HasSubstr("block 0: arc "));
  EXPECT_THAT(message, HasSubstr(" of length 1000 along "));
  EXPECT_THAT(message, HasSubstr(" does not match the coordinates of its nodes"));

  v1::TMesh missing = grid.proto();
  missing.mutable_blocks(0)->mutable_node_uvw()->RemoveLast();
  EXPECT_THAT(LoadError(missing), HasSubstr("block 0: nodeUvw lacks an endpoint of arc "));
}

}  // namespace
}  // namespace ispq
