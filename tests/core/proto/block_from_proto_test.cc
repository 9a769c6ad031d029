// SPDX-License-Identifier: Apache-2.0
// BlockInputFromProto on a block of a small grid mesh: a valid block decodes to the corners,
// edges, faces and lists the model then holds, with the edges in the order the message lists
// them; and each malformed part of the encoding is refused naming the block and the part. (The
// real-file table in tmesh_from_proto_test.cc covers wrong counts of corners, edges and faces, a
// duplicate corner, an edge key used as a corner and the self-adjacent flag.)
#include "core/proto/block_from_proto.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::ElementsAreArray;
using ::testing::HasSubstr;

// Block 0 is [0,1] x [0,2] x [0,1] with two blocks on its POS_U face, so it has edges of two
// arcs and a face of two patches; block 1 is in a rotated frame.
const testing::GridTMesh& Grid() {
  static const testing::GridTMesh* const kGrid = [] {
    testing::GridTMeshSpec spec;
    spec.blocks = {{{0, 0, 0}, {1, 2, 1}}, {{1, 0, 0}, {2, 1, 1}}, {{1, 1, 0}, {2, 2, 1}}};
    spec.block_rotations = {{1, 11}};
    absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(spec);
    EXPECT_TRUE(grid.ok()) << grid.status();
    return new testing::GridTMesh(*std::move(grid));
  }();
  return *kGrid;
}

IdRanges Ids() {
  const v1::TMesh& m = Grid().proto();
  return IdRanges({m.nodes_size(), m.arcs_size(), m.patches_size(), m.blocks_size()});
}

TEST(BlockFromProtoTest, AValidBlockDecodesToWhatTheModelHolds) {
  const TMesh mesh = testing::TMeshOrDie(Grid().proto());
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    const v1::Block& proto = Grid().proto().blocks(b);
    const absl::StatusOr<BlockInput> input = BlockInputFromProto(b, proto, Ids());
    ASSERT_TRUE(input.ok()) << input.status();
    for (int c = 0; c < kNumCorners; ++c) EXPECT_EQ(input->corners[c], mesh.block_corner(b, c));
    for (int e = 0; e < kNumEdges; ++e) {
      EXPECT_THAT(input->edges[e].arcs, ElementsAreArray(mesh.block_edge_arcs(b, e))) << e;
      ASSERT_EQ(input->edges[e].halfarcs.size(), input->edges[e].arcs.size());
      for (size_t i = 0; i < input->edges[e].arcs.size(); ++i) {
        EXPECT_EQ(ArcOf(input->edges[e].halfarcs[i]), input->edges[e].arcs[i]);
      }
    }
    for (Dir side : kAllDirs) {
      EXPECT_THAT(input->face_patches[DirIndex(side)],
                  ElementsAreArray(mesh.block_face_patches(b, side)));
    }
    EXPECT_THAT(input->halfpatches, ElementsAreArray(proto.halfpatches()));
    EXPECT_EQ(input->arcs.size(), mesh.block_arcs(b).size());
    EXPECT_EQ(input->node_uvw.size(), mesh.block_node_uvw(b).size());
  }
}

// edge_order is the order of the message's list, so that the first broken edge it lists is
// the one reported.
TEST(BlockFromProtoTest, EdgeOrderFollowsTheMessage) {
  v1::Block block = Grid().proto().blocks(0);
  const absl::StatusOr<BlockInput> as_listed = BlockInputFromProto(0, block, Ids());
  ASSERT_TRUE(as_listed.ok());
  std::reverse(block.mutable_edges()->begin(), block.mutable_edges()->end());
  const absl::StatusOr<BlockInput> reversed = BlockInputFromProto(0, block, Ids());
  ASSERT_TRUE(reversed.ok()) << reversed.status();
  std::vector<int8_t> expected(as_listed->edge_order.begin(), as_listed->edge_order.end());
  std::reverse(expected.begin(), expected.end());
  EXPECT_THAT(reversed->edge_order, ElementsAreArray(expected));
  for (int e = 0; e < kNumEdges; ++e) {
    EXPECT_THAT(reversed->edges[e].arcs, ElementsAreArray(as_listed->edges[e].arcs));
  }
}

struct Malformation {
  std::string name;
  std::function<void(v1::Block&)> mutate;
  std::string expected;  // substring of the message
};

v1::Face& FaceOn(v1::Block& b, v1::UVWDir side) {
  for (v1::Face& face : *b.mutable_faces()) {
    if (face.side() == side) return face;
  }
  return *b.mutable_faces(0);
}

constexpr int32_t kHuge = std::numeric_limits<int32_t>::max();

std::vector<Malformation> Malformations() {
  return {
      {"corner node out of range", [](v1::Block& b) { b.mutable_corners(2)->set_node(kHuge); },
       "block 1: corner node 2147483647 does not exist"},
      {"edge key is a face side", [](v1::Block& b) { b.mutable_edges(3)->set_edge(v1::POS_U); },
       "block 1: edge key POS_U is not an edge"},
      {"edge twice", [](v1::Block& b) { b.mutable_edges(4)->set_edge(b.edges(0).edge()); },
       "appears twice"},
      {"edge without arcs",
       [](v1::Block& b) {
         b.mutable_edges(5)->clear_arcs();
         b.mutable_edges(5)->clear_halfarcs();
       },
       " has no arcs"},
      {"edge arcs and halfarcs differ in number",
       [](v1::Block& b) { b.mutable_edges(6)->add_halfarcs(b.edges(6).halfarcs(0)); },
       "lists 1 arcs but 2 halfarcs"},
      {"edge halfarc of another arc",
       [](v1::Block& b) { b.mutable_edges(7)->set_halfarcs(0, b.edges(8).halfarcs(0)); },
       "is invalid"},
      {"edge arc out of range", [](v1::Block& b) { b.mutable_edges(7)->set_arcs(0, -1); },
       "arc -1 / halfarc"},
      {"face key is an edge", [](v1::Block& b) { b.mutable_faces(1)->set_side(v1::POS_U_POS_V); },
       "block 1: face key POS_U_POS_V is not a face side"},
      {"face twice", [](v1::Block& b) { b.mutable_faces(2)->set_side(b.faces(0).side()); },
       "appears twice"},
      {"face without patches", [](v1::Block& b) { b.mutable_faces(3)->clear_patches(); },
       " has no patches"},
      {"face patch out of range", [](v1::Block& b) { FaceOn(b, v1::NEG_W).add_patches(kHuge); },
       "block 1: face NEG_W patch 2147483647 does not exist"},
      {"face arc out of range", [](v1::Block& b) { FaceOn(b, v1::POS_W).add_arcs(-3); },
       "block 1: face POS_W arc -3 does not exist"},
      {"face node out of range", [](v1::Block& b) { FaceOn(b, v1::NEG_V).add_nodes(kHuge); },
       "block 1: face NEG_V node 2147483647 does not exist"},
      {"halfpatch out of range", [](v1::Block& b) { b.add_halfpatches(-1); },
       "block 1: halfpatch -1 does not exist"},
      {"arcsByDir key is an edge",
       [](v1::Block& b) { b.mutable_arcs_by_dir(0)->set_dir(v1::NEG_U_NEG_W); },
       "block 1: arcsByDir key NEG_U_NEG_W is not a direction"},
      {"arcsByDir direction twice",
       [](v1::Block& b) { b.mutable_arcs_by_dir(1)->set_dir(b.arcs_by_dir(0).dir()); }, " twice"},
      {"arcsByDir arc out of range",
       [](v1::Block& b) { b.mutable_arcs_by_dir(0)->add_arcs(kHuge); },
       "block 1: arcsByDir arc 2147483647 does not exist"},
      {"nodeUvw node out of range", [](v1::Block& b) { b.mutable_node_uvw(0)->set_node(-7); },
       "block 1: nodeUvw node -7 does not exist"},
      {"nodeUvw with two coordinates",
       [](v1::Block& b) { b.mutable_node_uvw(1)->mutable_uvw()->RemoveLast(); },
       "needs 3 coordinates"},
      {"nodeUvw not finite",
       [](v1::Block& b) {
         b.mutable_node_uvw(2)->set_uvw(1, std::numeric_limits<double>::infinity());
       },
       "is not finite"},
  };
}

class BlockMalformationTest : public ::testing::TestWithParam<Malformation> {};

TEST_P(BlockMalformationTest, IsRefusedNamingTheBlockAndPart) {
  v1::Block block = Grid().proto().blocks(1);
  GetParam().mutate(block);
  const absl::StatusOr<BlockInput> input = BlockInputFromProto(1, block, Ids());
  ASSERT_FALSE(input.ok()) << GetParam().name << " was accepted";
  EXPECT_EQ(input.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(input.status().message()), HasSubstr("block 1: "));
  EXPECT_THAT(std::string(input.status().message()), HasSubstr(GetParam().expected));
}

INSTANTIATE_TEST_SUITE_P(BlockFromProtoTest, BlockMalformationTest,
                         ::testing::ValuesIn(Malformations()),
                         [](const ::testing::TestParamInfo<Malformation>& info) {
                           std::string name;
                           for (char c : info.param.name) name += std::isalnum(c) ? c : '_';
                           return name;
                         });

}  // namespace
}  // namespace ispq
