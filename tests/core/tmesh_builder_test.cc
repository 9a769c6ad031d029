// SPDX-License-Identifier: Apache-2.0
// TMeshBuilder on plain data, without protobuf: a unit cube (one block, six boundary patches)
// written out element by element is built with its derived adjacency and critical entities,
// broken rules are reported by element, and calls out of order are refused. The rules themselves
// are covered on real meshes by tmesh_from_proto_test.cc.
#include "core/tmesh_builder.h"

#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/resolution_levels.h"
#include "core/status_macros.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::SizeIs;

constexpr std::array<int, 3> Bits(int corner) {
  return {corner & 1, (corner >> 1) & 1, corner >> 2};
}

// The unit cube in its own frame: node c is corner c, arc e is edge e (from its NEG to its POS
// corner), patch p lies on face kAllDirs[p] with its cycle counterclockwise around the normal
// into the block, so that the two patches at an arc run along it in opposite directions.
class UnitCube {
 public:
  UnitCube() {
    for (int e = 0; e < kNumEdges; ++e) AddArc(e);
    for (Dir side : kAllDirs) AddFace(side);
    for (int e = 0; e < kNumEdges; ++e) {
      for (PatchId p = 0; p < kNumDirs; ++p) {
        for (HalfarcId h : cycles_[p]) {
          if (ArcOf(h) == e) arc_halfpatches_[e].push_back(2 * p + (h & 1));
        }
      }
    }
  }

  NodeInput Node(NodeId n) const {
    // Three singular arcs meet at every corner: each node is SINGULAR and critical.
    return {.outgoing_halfarcs = outgoing_[n],
            .critical = true,
            .boundary = true,
            .singular_type = SingularType::kSingular};
  }
  ArcInput Arc(ArcId a) const {
    // A block edge on the boundary: one quarter turn where a flat boundary has two, singular.
    return {.from = from_[a],
            .to = to_[a],
            .length = 1.0,
            .singular = -1,
            .boundary = true,
            .critical = true,
            .halfpatches = arc_halfpatches_[a]};
  }
  PatchInput Patch(PatchId p) const {
    PatchInput patch;
    patch.blocks = {0, kNoId};
    patch.face_sides = {kAllDirs[p], Dir::kPosU};
    patch.boundary = true;
    patch.critical = true;
    patch.cycle = cycles_[p];
    patch.ref_block = 0;
    for (int i = 0; i < 4; ++i) {
      const HalfarcId& h = cycles_[p][i];
      patch.sides[i] = {MakeDir(EdgeAxis(ArcOf(h)), (h & 1) != 0), {&h, 1}};
    }
    return patch;
  }
  BlockInput Block() const {
    BlockInput block;
    for (int c = 0; c < kNumCorners; ++c) {
      block.corners[c] = c;
      const std::array<int, 3> bits = Bits(c);
      block.node_uvw.push_back({c, {1.0 * bits[0], 1.0 * bits[1], 1.0 * bits[2]}});
    }
    for (int e = 0; e < kNumEdges; ++e) {
      block.edges[e] = {{&edge_arcs_[e], 1}, {&edge_halfarcs_[e], 1}};
      block.edge_order[e] = static_cast<int8_t>(e);
      block.arcs.push_back({e, MakeDir(EdgeAxis(e), false)});
    }
    for (PatchId p = 0; p < kNumDirs; ++p) block.face_patches[p] = {&patch_ids_[p], 1};
    block.halfpatches = side0_halfpatches_;
    return block;
  }

 private:
  void AddArc(int e) {
    const int axis = EdgeAxis(e);
    const int first = axis == 0 ? 1 : 0, second = axis == 2 ? 1 : 2;
    const int low = ((e & 1) << first) | (((e & 2) >> 1) << second);
    from_[e] = low;
    to_[e] = low | (1 << axis);
    outgoing_[from_[e]].push_back(2 * e);
    outgoing_[to_[e]].push_back(2 * e + 1);
    edge_arcs_[e] = e;
    edge_halfarcs_[e] = 2 * e;
  }
  HalfarcId HalfarcBetween(NodeId tail, NodeId head) const {
    for (int e = 0; e < kNumEdges; ++e) {
      if (from_[e] == tail && to_[e] == head) return 2 * e;
      if (from_[e] == head && to_[e] == tail) return 2 * e + 1;
    }
    return kNoId;
  }
  void AddFace(Dir side) {
    const PatchId p = DirIndex(side);
    const int axis = AxisOf(side), u1 = (axis + 1) % 3, u2 = (axis + 2) % 3;
    // Counterclockwise around +axis in (u1, u2); reversed where the inward normal is -axis.
    std::array<std::array<int, 2>, 4> square = {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    if (!IsNegative(side)) std::swap(square[1], square[3]);
    std::array<NodeId, 4> corners;
    for (int i = 0; i < 4; ++i) {
      corners[i] = (IsNegative(side) ? 0 : 1 << axis) | (square[i][0] << u1) | (square[i][1] << u2);
    }
    for (int i = 0; i < 4; ++i) {
      cycles_[p].push_back(HalfarcBetween(corners[i], corners[(i + 1) % 4]));
    }
    patch_ids_[p] = p;
    side0_halfpatches_.push_back(2 * p);
  }

  std::array<NodeId, kNumEdges> from_{}, to_{};
  std::array<std::vector<HalfarcId>, kNumCorners> outgoing_;
  std::array<std::vector<HalfpatchId>, kNumEdges> arc_halfpatches_;
  std::array<std::vector<HalfarcId>, kNumDirs> cycles_;
  std::array<ArcId, kNumEdges> edge_arcs_{};
  std::array<HalfarcId, kNumEdges> edge_halfarcs_{};
  std::array<PatchId, kNumDirs> patch_ids_{};
  std::vector<HalfpatchId> side0_halfpatches_;
};

TMeshHeader CubeHeader() {
  TMeshHeader header;
  header.name = "cube";
  header.sizes = {kNumCorners, kNumEdges, kNumDirs, 1};
  return header;
}

// Adds every element of the cube, letting `edit` change the inputs first.
struct Edits {
  std::function<void(ArcId, ArcInput&)> arc = [](ArcId, ArcInput&) {};
  std::function<void(NodeId, NodeInput&)> node = [](NodeId, NodeInput&) {};
  std::function<void(PatchId, PatchInput&)> patch = [](PatchId, PatchInput&) {};
  std::function<void(BlockInput&)> block = [](BlockInput&) {};
};

absl::Status AddCube(const UnitCube& cube, TMeshBuilder& builder, const Edits& edits = {}) {
  for (NodeId n = 0; n < kNumCorners; ++n) {
    NodeInput node = cube.Node(n);
    edits.node(n, node);
    ISPQ_RETURN_IF_ERROR(builder.AddNode(node));
  }
  for (ArcId a = 0; a < kNumEdges; ++a) {
    ArcInput arc = cube.Arc(a);
    edits.arc(a, arc);
    ISPQ_RETURN_IF_ERROR(builder.AddArc(arc));
  }
  for (PatchId p = 0; p < kNumDirs; ++p) {
    PatchInput patch = cube.Patch(p);
    edits.patch(p, patch);
    ISPQ_RETURN_IF_ERROR(builder.AddPatch(patch));
  }
  BlockInput block = cube.Block();
  edits.block(block);
  return builder.AddBlock(std::move(block));
}

absl::StatusOr<TMesh> BuildCube(const Edits& edits = {}) {
  const UnitCube cube;
  ISPQ_ASSIGN_OR_RETURN(TMeshBuilder builder, TMeshBuilder::Create(CubeHeader()));
  ISPQ_RETURN_IF_ERROR(AddCube(cube, builder, edits));
  ISPQ_RETURN_IF_ERROR(builder.Connect());
  ISPQ_RETURN_IF_ERROR(builder.DeriveCriticalEntities({}));
  return std::move(builder).Build();
}

TEST(TMeshBuilderTest, BuildsTheCubeAndDerivesItsAdjacency) {
  const absl::StatusOr<TMesh> mesh = BuildCube();
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  EXPECT_EQ(mesh->name(), "cube");
  for (NodeId n = 0; n < mesh->num_nodes(); ++n) {
    EXPECT_THAT(mesh->node_blocks(n), ElementsAre(0));
    EXPECT_THAT(mesh->node_halfpatches(n), SizeIs(6)) << n;  // both sides of 3 patches
  }
  for (ArcId a = 0; a < mesh->num_arcs(); ++a) {
    EXPECT_THAT(mesh->arc_blocks(a), ElementsAre(0));
    EXPECT_EQ(mesh->HalfarcDirInBlock(2 * a, 0), MakeDir(EdgeAxis(a), false));
  }
  // 8 corner nodes, 12 links (every arc joins two critical nodes), 6 one-patch regions (every
  // arc between two patches is critical).
  EXPECT_EQ(mesh->num_entities(), 8 + 12 + 6);
  EXPECT_EQ(mesh->entity_dim(8), EntityDim::kLink);
  EXPECT_EQ(mesh->entity_dim(20), EntityDim::kRegion);
}

TEST(TMeshBuilderTest, ReportsTheFirstBrokenElement) {
  Edits edits;
  edits.arc = [](ArcId a, ArcInput& arc) {
    if (a == 3 || a == 5) arc.length = 0;
  };
  const absl::StatusOr<TMesh> mesh = BuildCube(edits);
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(mesh.status().message(), "arc 3: length 0 is not a positive finite number");
}

TEST(TMeshBuilderTest, ConnectChecksHowElementsFitTogether) {
  Edits edits;
  edits.node = [](NodeId n, NodeInput& node) {
    if (n == 0) node.outgoing_halfarcs = node.outgoing_halfarcs.first(2);
  };
  const absl::StatusOr<TMesh> mesh = BuildCube(edits);
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(mesh.status().message()), HasSubstr("node 0: outgoing halfarc"));
  EXPECT_THAT(std::string(mesh.status().message()), HasSubstr("is missing"));
}

TEST(TMeshBuilderTest, NodeTypesFollowTheirArcs) {
  Edits edits;
  edits.node = [](NodeId n, NodeInput& node) {
    if (n == 3) node.singular_type = SingularType::kSemiSingular;
  };
  EXPECT_EQ(BuildCube(edits).status().message(),
            "node 3: singularType SEMI_SINGULAR but 3 singular arcs meet there (SINGULAR)");
  edits.node = [](NodeId n, NodeInput& node) {
    if (n == 6) node.feature_type = FeatureType::kFeature;
  };
  EXPECT_EQ(BuildCube(edits).status().message(),
            "node 6: featureType FEATURE but its marks make it REGULAR (0 feature and 3 singular "
            "arcs, not a feature node)");
}

TEST(TMeshBuilderTest, AHalfpatchFacesItsBlock) {
  // Patch 2 (face POS_V) put on the block's side of its other halfpatch, whose cycle runs the
  // other way round: everything still names everything else consistently, but halfpatch 5
  // turns about the outward normal.
  const std::vector<HalfpatchId> halfpatches = {0, 2, 5, 6, 8, 10};
  Edits edits;
  edits.patch = [](PatchId p, PatchInput& patch) {
    if (p != 2) return;
    patch.blocks = {kNoId, 0};
    patch.face_sides = {Dir::kPosU, Dir::kPosV};
  };
  edits.block = [&halfpatches](BlockInput& block) { block.halfpatches = halfpatches; };
  const absl::StatusOr<TMesh> mesh = BuildCube(edits);
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(mesh.status().message()),
              HasSubstr("patch 2: the cycle of halfpatch 5 turns about POS_V at node "));
  EXPECT_THAT(std::string(mesh.status().message()),
              HasSubstr("where it must turn about NEG_V, the normal into block 0"));
}

TEST(TMeshBuilderTest, ChecksAListedEntityListAndLevels) {
  const UnitCube cube;
  absl::StatusOr<TMeshBuilder> builder = TMeshBuilder::Create(CubeHeader());
  ASSERT_TRUE(builder.ok());
  ASSERT_TRUE(AddCube(cube, *builder).ok());
  ASSERT_TRUE(builder->Connect().ok());
  CriticalEntity node_5;
  node_5.node_from = node_5.node_to = 5;
  EXPECT_EQ(builder->DeriveCriticalEntities({&node_5, 1}).message(),
            "critical entity 0: the mesh makes it node 0, the request says node 5");

  absl::StatusOr<TMeshBuilder> fresh = TMeshBuilder::Create(CubeHeader());
  ASSERT_TRUE(AddCube(cube, *fresh).ok());
  ASSERT_TRUE(fresh->Connect().ok());
  ASSERT_TRUE(fresh->DeriveCriticalEntities({}).ok());
  const std::vector<double> lengths(kNumEdges, 1.0);
  EXPECT_TRUE(fresh->AddLevel({100, *ScalingForPercent(lengths, 100)}).ok());
  EXPECT_THAT(std::string(fresh->AddLevel({50, 123.0}).message()),
              HasSubstr("level 1: scaling 123 for 50% should be "));
}

TEST(TMeshBuilderTest, RefusesCallsOutOfOrder) {
  const UnitCube cube;
  absl::StatusOr<TMeshBuilder> builder = TMeshBuilder::Create(CubeHeader());
  ASSERT_TRUE(builder.ok());
  EXPECT_EQ(builder->AddArc(cube.Arc(0)).code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(builder->Connect().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_EQ(std::move(*builder).Build().status().code(), absl::StatusCode::kFailedPrecondition);
}

TEST(TMeshBuilderTest, RefusesEmptyAndOversizedMeshes) {
  TMeshHeader header = CubeHeader();
  header.sizes.patches = 0;
  EXPECT_EQ(TMeshBuilder::Create(header).status().message(), "the mesh has no patches");
  header.sizes.patches = 1 << 30;
  EXPECT_EQ(TMeshBuilder::Create(header).status().message(),
            "the mesh has too many patches: 1073741824");
}

}  // namespace
}  // namespace ispq
