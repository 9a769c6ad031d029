// SPDX-License-Identifier: Apache-2.0
// The incidence rules on small grid meshes: every built mesh passes each check, and lists that
// disagree are reported naming the element whose list is wrong. A TMesh whose lists disagree
// cannot exist, so the broken cases are grid messages with one list edited, loaded through
// TMeshFromProto; the kinds the real-file table (tests/core/proto/tmesh_from_proto_test.cc)
// already covers (a foreign or missing outgoing halfarc, wrong arc halfpatches, a foreign
// halfpatch or patch on a block, a block not listing a halfpatch) are not repeated here.
#include "core/tmesh_incidence_checks.h"

#include <algorithm>
#include <string>
#include <utility>

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

// Block 0 is [0,1] x [0,2] x [0,1]; blocks 1 and 2 sit on its POS_U face, one per half, so that
// face has two patches.
GridTMeshSpec TJunction() {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 2, 1}}, {{1, 0, 0}, {2, 1, 1}}, {{1, 1, 0}, {2, 2, 1}}};
  return spec;
}

std::string LoadError(const v1::TMesh& proto) {
  const absl::StatusOr<TMesh> mesh = TMeshFromProto(proto);
  EXPECT_FALSE(mesh.ok());
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  return std::string(mesh.status().message());
}

TEST(TMeshIncidenceChecksTest, BuiltMeshesPass) {
  GridTMeshSpec rotated = TJunction();
  rotated.block_rotations = {{1, 7}, {2, 13}};
  for (const GridTMeshSpec& spec : {TJunction(), rotated}) {
    const TMesh mesh = testing::TMeshOrDie(testing::BuildGridTMeshOrDie(spec).proto());
    EXPECT_TRUE(CheckNodeArcIncidence(mesh).ok());
    EXPECT_TRUE(CheckArcPatchIncidence(mesh).ok());
    EXPECT_TRUE(CheckPatchBlockIncidence(mesh).ok());
    EXPECT_TRUE(CheckArcBlocks(mesh).ok());
  }
}

TEST(TMeshIncidenceChecksTest, AnOutgoingHalfarcListedTwiceIsNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(TJunction());
  const int n = grid.NodeAt({1, 1, 0});
  v1::TMesh proto = grid.proto();
  const int32_t h = proto.nodes(n).outgoing_halfarcs(0);
  proto.mutable_nodes(n)->add_outgoing_halfarcs(h);
  EXPECT_EQ(LoadError(proto), "node " + std::to_string(n) + ": outgoing halfarc " +
                                  std::to_string(h) + " listed twice");
}

// An arc that lists the halfpatch of a patch whose cycle does not contain it, on top of its own:
// the message lists both sets.
TEST(TMeshIncidenceChecksTest, AnArcListingAnExtraHalfpatchIsNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(TJunction());
  const int a = grid.ArcBetween({0, 0, 0}, {0, 0, 1});
  const int far = grid.PatchAt({{2, 1, 0}, {2, 2, 1}});
  v1::TMesh proto = grid.proto();
  proto.mutable_arcs(a)->add_halfpatches(2 * far);
  const std::string message = LoadError(proto);
  EXPECT_THAT(message, HasSubstr("arc " + std::to_string(a) + ": halfpatches ["));
  EXPECT_THAT(message, HasSubstr(absl::StrCat(
                           ",", 2 * far, "] differ from the patches whose cycles contain it [")));
}

TEST(TMeshIncidenceChecksTest, AFaceThatDoesNotListItsPatchIsNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(TJunction());
  const int p = grid.PatchAt({{1, 0, 0}, {1, 1, 1}});
  ASSERT_NE(p, -1);
  v1::TMesh proto = grid.proto();
  ASSERT_EQ(proto.patches(p).blocks(0), 0);
  bool removed = false;
  for (v1::Face& face : *proto.mutable_blocks(0)->mutable_faces()) {
    auto* patches = face.mutable_patches();
    const auto it = std::find(patches->begin(), patches->end(), p);
    if (it == patches->end()) continue;
    ASSERT_EQ(patches->size(), 2);  // the other half keeps the face non-empty
    patches->erase(it);
    removed = true;
  }
  ASSERT_TRUE(removed);
  EXPECT_EQ(LoadError(proto), "patch " + std::to_string(p) +
                                  ": lies on face POS_U of block 0 but that face does not list it");
}

// Block 0 lists, with consistent coordinates, an arc of block 1's far face that it does not
// touch: only the arc -> blocks check sees it.
TEST(TMeshIncidenceChecksTest, ABlockListingAnArcItIsNotAroundIsNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(TJunction());
  const int a = grid.ArcBetween({2, 0, 0}, {2, 1, 0});
  ASSERT_NE(a, -1);
  v1::TMesh proto = grid.proto();
  v1::Block& block = *proto.mutable_blocks(0);
  for (v1::DirectedArcs& entry : *block.mutable_arcs_by_dir()) {
    if (entry.dir() == v1::POS_V) entry.add_arcs(a);
  }
  for (const int n : {grid.NodeAt({2, 0, 0}), grid.NodeAt({2, 1, 0})}) {
    v1::NodeUvw* uvw = block.add_node_uvw();
    uvw->set_node(n);
    for (int i = 0; i < 3; ++i) uvw->add_uvw(grid.node_point(n)[i]);  // block 0: global frame
  }
  EXPECT_EQ(LoadError(proto), "arc " + std::to_string(a) +
                                  ": the blocks around it [1] differ from the blocks listing it "
                                  "in arcsByDir [0,1]");
}

}  // namespace
}  // namespace ispq
