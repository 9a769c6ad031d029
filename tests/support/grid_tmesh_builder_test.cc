// SPDX-License-Identifier: Apache-2.0
#include "tests/support/grid_tmesh_builder.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "core/direction.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/rotation.h"
#include "core/tmesh.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"
#include "tests/support/worked_examples.h"

namespace ispq::testing {
namespace {

using ::testing::ElementsAre;

// Builds the mesh, requires it to pass the validator and to survive a JSON round trip
// unchanged. A spec the builder rejects aborts the binary, as test_data.h does for invalid
// inputs: every later lookup would index an empty mesh. With ISPQ_GRID_TMESH_DUMP_DIR set, the
// JSON is also written there as <name>.tmesh.json, e.g. to look at with `ispq stats`.
GridTMesh BuildValid(const GridTMeshSpec& spec) {
  absl::StatusOr<GridTMesh> mesh = BuildGridTMesh(spec);
  if (!mesh.ok()) {
    std::cerr << "cannot build " << spec.name << ": " << mesh.status() << "\n";
    std::abort();
  }
  const absl::StatusOr<TMesh> validated = TMeshFromProto(mesh->proto());
  EXPECT_TRUE(validated.ok()) << spec.name << ": " << validated.status();
  const absl::StatusOr<std::string> json = TMeshToJson(mesh->proto());
  EXPECT_TRUE(json.ok()) << json.status();
  if (json.ok()) {
    const absl::StatusOr<v1::TMesh> parsed = ParseTMeshJson(*json);
    EXPECT_TRUE(parsed.ok()) << parsed.status();
    if (parsed.ok()) {
      EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(*parsed, mesh->proto()))
          << spec.name << ": JSON round trip changed the mesh";
    }
    if (const char* dir = std::getenv("ISPQ_GRID_TMESH_DUMP_DIR"); dir != nullptr) {
      std::ofstream(std::string(dir) + "/" + spec.name + ".tmesh.json") << *json;
    }
  }
  return *std::move(mesh);
}

std::vector<int> EntityCounts(const v1::TMesh& mesh) {
  std::vector<int> counts(3, 0);
  for (const v1::CriticalEntity& e : mesh.critical_entities()) ++counts[e.dim()];
  return counts;
}

GridTMeshSpec UnitCube() {
  GridTMeshSpec spec;
  spec.name = "unit_cube";
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  return spec;
}

TEST(GridTMeshBuilderTest, UnitCubeHasTheReferenceCubesStructure) {
  const GridTMesh mesh = BuildValid(UnitCube());
  const v1::TMesh& built = mesh.proto();
  const v1::TMesh reference = LoadProtoOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  EXPECT_EQ(built.nodes_size(), reference.nodes_size());
  EXPECT_EQ(built.arcs_size(), reference.arcs_size());
  EXPECT_EQ(built.patches_size(), reference.patches_size());
  EXPECT_EQ(built.blocks_size(), reference.blocks_size());
  EXPECT_EQ(EntityCounts(built), EntityCounts(reference));
  EXPECT_THAT(EntityCounts(built), ElementsAre(8, 12, 6));
  EXPECT_EQ(built.stats().critical_nodes(), reference.stats().critical_nodes());
  EXPECT_EQ(built.stats().critical_arcs(), reference.stats().critical_arcs());
  EXPECT_EQ(built.stats().singular_arcs(), reference.stats().singular_arcs());
  for (const v1::Node& node : built.nodes()) {
    EXPECT_EQ(node.singular_type(), v1::SingularType::SINGULAR);
    EXPECT_TRUE(node.critical());
  }
  for (const v1::Arc& arc : built.arcs()) {
    EXPECT_EQ(arc.singular(), -1);
    EXPECT_EQ(arc.length(), 1.0);
  }
  for (const v1::CriticalEntity& e : built.critical_entities()) {
    EXPECT_EQ(e.halfarcs_size(), e.dim() == 1 ? 1 : 0);
    EXPECT_EQ(e.patches_size(), e.dim() == 2 ? 1 : 0);
  }
  EXPECT_FALSE(built.features_present().nodes());
}

// A node's flags, looked up by grid point.
const v1::Node& NodeAt(const GridTMesh& mesh, const GridPoint& p) {
  const int n = mesh.NodeAt(p);
  EXPECT_GE(n, 0) << "no node at " << p[0] << "," << p[1] << "," << p[2];
  return mesh.proto().nodes(std::max(n, 0));
}

const v1::Arc& ArcBetween(const GridTMesh& mesh, const GridPoint& a, const GridPoint& b) {
  const int arc = mesh.ArcBetween(a, b);
  EXPECT_GE(arc, 0) << "no arc " << a[0] << "," << a[1] << "," << a[2] << " - " << b[0] << ","
                    << b[1] << "," << b[2];
  return mesh.proto().arcs(std::max(arc, 0));
}

const v1::Block& Block(const GridTMesh& mesh, int b) { return mesh.proto().blocks(b); }

std::vector<int> EdgeArcs(const v1::Block& block, v1::UVWDir edge) {
  for (const v1::Edge& e : block.edges()) {
    if (e.edge() == edge) return {e.arcs().begin(), e.arcs().end()};
  }
  ADD_FAILURE() << "no edge " << v1::UVWDir_Name(edge);
  return {};
}

const v1::Face& Face(const v1::Block& block, v1::UVWDir side) {
  for (const v1::Face& f : block.faces()) {
    if (f.side() == side) return f;
  }
  ADD_FAILURE() << "no face " << v1::UVWDir_Name(side);
  return block.faces(0);
}

GridTMeshSpec TwoBlocksAlongU() {
  GridTMeshSpec spec;
  spec.name = "two_blocks_along_u";
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
  spec.spacing[0] = {2.0, 3.0};
  return spec;
}

// T5: the wall nodes and wall arcs lie on flat boundary and are not critical.
TEST(GridTMeshBuilderTest, TwoBlocksAlongUHaveNonCriticalWalls) {
  const GridTMesh mesh = BuildValid(TwoBlocksAlongU());
  const v1::TMesh& proto = mesh.proto();
  EXPECT_EQ(proto.nodes_size(), 12);
  EXPECT_EQ(proto.arcs_size(), 20);
  EXPECT_EQ(proto.patches_size(), 11);
  EXPECT_THAT(EntityCounts(proto), ElementsAre(8, 12, 6));
  for (int v : {0, 1}) {
    for (int w : {0, 1}) {
      const v1::Node& wall = NodeAt(mesh, {1, v, w});
      EXPECT_EQ(wall.singular_type(), v1::SingularType::SEMI_SINGULAR);
      EXPECT_FALSE(wall.critical());
      // The u-edge link runs through the wall node.
      EXPECT_EQ(mesh.HalfarcChain({0, v, w}, {2, v, w}).size(), 2u);
    }
  }
  for (const auto& [a, b] : std::vector<std::pair<GridPoint, GridPoint>>{
           {{1, 0, 0}, {1, 1, 0}}, {{1, 0, 1}, {1, 1, 1}}, {{1, 0, 0}, {1, 0, 1}}}) {
    const v1::Arc& arc = ArcBetween(mesh, a, b);
    EXPECT_TRUE(arc.boundary());
    EXPECT_EQ(arc.singular(), 0);
    EXPECT_FALSE(arc.critical());
  }
  EXPECT_EQ(ArcBetween(mesh, {0, 0, 0}, {1, 0, 0}).length(), 2.0);
  EXPECT_EQ(ArcBetween(mesh, {1, 0, 0}, {2, 0, 0}).length(), 3.0);
  // The wall patch: identity rotation, translation between the blocks' origins.
  const int wall = mesh.PatchAt({{1, 0, 0}, {1, 1, 1}});
  ASSERT_GE(wall, 0);
  const v1::Patch& patch = proto.patches(wall);
  EXPECT_THAT(patch.blocks(), ElementsAre(0, 1));
  EXPECT_THAT(patch.sides(), ElementsAre(v1::POS_U, v1::NEG_U));
  EXPECT_THAT(patch.transition().rotation(), ElementsAre(1, 2, 3));
  EXPECT_THAT(patch.transition().translation(), ElementsAre(-2.0, 0.0, 0.0));
  // Each of the four long sides is one region of two patches, the ends one patch each.
  std::vector<int> region_sizes;
  for (const v1::CriticalEntity& e : proto.critical_entities()) {
    if (e.dim() == 2) region_sizes.push_back(e.patches_size());
  }
  EXPECT_THAT(region_sizes, ::testing::UnorderedElementsAre(1, 1, 2, 2, 2, 2));
}

// T6: a 2x2x2 grid of unit blocks with its centre node marked as a feature node.
GridTMeshSpec GridWithFeatureCentre() {
  GridTMeshSpec spec;
  spec.name = "grid_2x2x2_feature_centre";
  for (int w = 0; w < 2; ++w) {
    for (int v = 0; v < 2; ++v) {
      for (int u = 0; u < 2; ++u) spec.blocks.push_back({{u, v, w}, {u + 1, v + 1, w + 1}});
    }
  }
  spec.feature_nodes = {{1, 1, 1}};
  return spec;
}

TEST(GridTMeshBuilderTest, GridWithFeatureCentreHasOneInteriorCriticalNode) {
  const GridTMesh mesh = BuildValid(GridWithFeatureCentre());
  const v1::TMesh& proto = mesh.proto();
  EXPECT_EQ(proto.nodes_size(), 27);
  EXPECT_EQ(proto.arcs_size(), 54);
  EXPECT_EQ(proto.patches_size(), 36);
  EXPECT_THAT(EntityCounts(proto), ElementsAre(9, 12, 6));
  EXPECT_TRUE(proto.features_present().nodes());
  EXPECT_FALSE(proto.features_present().arcs());
  const v1::Node& centre = NodeAt(mesh, {1, 1, 1});
  EXPECT_TRUE(centre.feature());
  EXPECT_FALSE(centre.boundary());
  EXPECT_EQ(centre.feature_type(), v1::FeatureType::FEATURE);
  EXPECT_EQ(centre.singular_type(), v1::SingularType::REGULAR);
  EXPECT_TRUE(centre.critical());
  EXPECT_FALSE(NodeAt(mesh, {1, 1, 0}).critical());  // bottom face centre
  EXPECT_EQ(NodeAt(mesh, {1, 0, 0}).singular_type(), v1::SingularType::SEMI_SINGULAR);
  EXPECT_FALSE(NodeAt(mesh, {1, 0, 0}).critical());  // middle of a cube edge
  // The arc from the centre down to the bottom face centre (the row of T6) is interior.
  const v1::Arc& down = ArcBetween(mesh, {1, 1, 0}, {1, 1, 1});
  EXPECT_FALSE(down.boundary());
  EXPECT_FALSE(down.critical());
  EXPECT_EQ(down.halfpatches_size(), 4);
  for (const v1::CriticalEntity& e : proto.critical_entities()) {
    if (e.dim() == 1) {
      EXPECT_EQ(e.halfarcs_size(), 2);
    } else if (e.dim() == 2) {
      EXPECT_EQ(e.patches_size(), 4);
    }
  }
}

// A block next to a taller one: its top face meets the tall block's side at a concave edge, and
// its corners split the tall block's edges (T-junctions).
TEST(GridTMeshBuilderTest, StepMakesTJunctionsAndAConcaveEdge) {
  GridTMeshSpec spec;
  spec.name = "step_t_junction";
  spec.blocks = {{{0, 0, 0}, {1, 1, 2}}, {{1, 0, 0}, {2, 1, 1}}};
  const GridTMesh mesh = BuildValid(spec);
  const v1::TMesh& proto = mesh.proto();
  EXPECT_EQ(proto.nodes_size(), 14);
  EXPECT_EQ(proto.patches_size(), 12);
  const v1::Block& tall = Block(mesh, 0);
  EXPECT_EQ(EdgeArcs(tall, v1::POS_U_NEG_V).size(), 2u);
  EXPECT_EQ(EdgeArcs(tall, v1::POS_U_POS_V).size(), 2u);
  EXPECT_EQ(EdgeArcs(tall, v1::NEG_U_NEG_V).size(), 1u);
  const v1::Face& side = Face(tall, v1::POS_U);
  EXPECT_EQ(side.patches_size(), 2);  // the wall to the low block and the boundary above it
  const int concave = mesh.ArcBetween({1, 0, 1}, {1, 1, 1});
  EXPECT_THAT(side.arcs(), ElementsAre(concave));
  EXPECT_THAT(side.nodes(), ::testing::IsEmpty());
  EXPECT_EQ(proto.arcs(concave).singular(), 1);
  EXPECT_EQ(proto.arcs(concave).halfpatches_size(), 3);  // wall, boundary above, top of B
  for (int v : {0, 1}) {
    const v1::Node& t_junction = NodeAt(mesh, {1, v, 1});
    EXPECT_EQ(t_junction.singular_type(), v1::SingularType::SINGULAR);  // 3 sharp edges
    EXPECT_TRUE(t_junction.critical());
    EXPECT_EQ(ArcBetween(mesh, {1, v, 0}, {1, v, 1}).singular(), 0);  // flat wall edge
  }
}

// A small block on part of a larger block's top face: the face is split into the wall under the
// small block and boundary rectangles around it, with a node and arcs strictly inside it.
TEST(GridTMeshBuilderTest, BlockOnPartOfAFaceSplitsIt) {
  GridTMeshSpec spec;
  spec.name = "block_on_a_face";
  spec.blocks = {{{0, 0, 0}, {2, 2, 1}}, {{0, 0, 1}, {1, 1, 2}}};
  const GridTMesh mesh = BuildValid(spec);
  const v1::Face& top = Face(Block(mesh, 0), v1::POS_W);
  EXPECT_EQ(top.patches_size(), 3);
  EXPECT_THAT(top.nodes(), ElementsAre(mesh.NodeAt({1, 1, 1})));
  EXPECT_THAT(top.arcs(), ::testing::UnorderedElementsAre(mesh.ArcBetween({1, 0, 1}, {1, 1, 1}),
                                                          mesh.ArcBetween({0, 1, 1}, {1, 1, 1}),
                                                          mesh.ArcBetween({1, 1, 1}, {1, 2, 1})));
  EXPECT_EQ(ArcBetween(mesh, {1, 0, 1}, {1, 1, 1}).singular(), 1);
  EXPECT_EQ(ArcBetween(mesh, {1, 1, 1}, {1, 2, 1}).singular(), 0);
  EXPECT_TRUE(NodeAt(mesh, {1, 1, 1}).critical());
  EXPECT_EQ(EdgeArcs(Block(mesh, 0), v1::NEG_V_POS_W).size(), 2u);
}

TEST(GridTMeshBuilderTest, LShapeHasAConcaveEdge) {
  GridTMeshSpec spec;
  spec.name = "l_shape";
  spec.blocks = {{{0, 0, 0}, {2, 1, 1}}, {{0, 1, 0}, {1, 2, 1}}};
  const GridTMesh mesh = BuildValid(spec);
  const v1::TMesh& proto = mesh.proto();
  EXPECT_EQ(proto.nodes_size(), 14);
  EXPECT_EQ(ArcBetween(mesh, {1, 1, 0}, {1, 1, 1}).singular(), 1);
  EXPECT_EQ(ArcBetween(mesh, {1, 1, 0}, {2, 1, 0}).singular(), -1);
  EXPECT_EQ(ArcBetween(mesh, {0, 1, 0}, {1, 1, 0}).singular(), 0);
  EXPECT_TRUE(NodeAt(mesh, {1, 1, 0}).critical());
  EXPECT_FALSE(NodeAt(mesh, {0, 1, 0}).critical());
  // 12 corners of the L prism; 6 outline edges per cap plus 6 vertical edges; 2 caps and 6
  // sides.
  EXPECT_THAT(EntityCounts(proto), ElementsAre(12, 18, 8));
}

// Every rotation of the second block of a two-block mesh, and of both blocks at once.
TEST(GridTMeshBuilderTest, RotatedFramesValidate) {
  const GridTMesh plain = BuildValid(TwoBlocksAlongU());
  const int wall = plain.PatchAt({{1, 0, 0}, {1, 1, 1}});
  for (int r = 0; r < Rotation::kCount; ++r) {
    SCOPED_TRACE(r);
    GridTMeshSpec spec = TwoBlocksAlongU();
    spec.name = absl::StrCat("two_blocks_rotated_", r);
    spec.block_rotations = {{1, r}};
    const GridTMesh mesh = BuildValid(spec);
    const v1::Transition& transition = mesh.proto().patches(wall).transition();
    const std::array<int, 3> expected = Rotation::FromIndex(r).SignedPermutation();
    EXPECT_THAT(transition.rotation(), ElementsAre(expected[0], expected[1], expected[2]));
    EXPECT_EQ(EntityCounts(mesh.proto()), EntityCounts(plain.proto()));

    spec.block_rotations = {{0, r}, {1, (r + 7) % Rotation::kCount}};
    const GridTMesh both = BuildValid(spec);
    const Rotation composed =
        Rotation::FromIndex((r + 7) % Rotation::kCount).After(Rotation::FromIndex(r).Inverse());
    const std::array<int, 3> chained = composed.SignedPermutation();
    EXPECT_THAT(both.proto().patches(wall).transition().rotation(),
                ElementsAre(chained[0], chained[1], chained[2]));
  }
}

// T10's frames: the bottom layer of the T6 grid turned by 90 degrees about w.
TEST(GridTMeshBuilderTest, RotatedLayerOfTheFeatureGridValidates) {
  const std::optional<Rotation> quarter_turn = Rotation::FromSignedPermutation({-2, 1, 3});
  ASSERT_TRUE(quarter_turn.has_value());
  GridTMeshSpec spec = GridWithFeatureCentre();
  spec.name = "grid_2x2x2_rotated_bottom";
  for (int b = 0; b < 4; ++b) spec.block_rotations.push_back({b, quarter_turn->index()});
  const GridTMesh mesh = BuildValid(spec);
  const int between_layers = mesh.PatchAt({{0, 0, 1}, {1, 1, 1}});
  ASSERT_GE(between_layers, 0);
  // From a bottom block to the top block above it: the inverse quarter turn.
  EXPECT_THAT(mesh.proto().patches(between_layers).transition().rotation(), ElementsAre(2, -1, 3));
  for (int r = 0; r < Rotation::kCount; ++r) {
    spec.block_rotations = {{0, r}, {7, r}};
    spec.name = absl::StrCat("grid_2x2x2_rotated_", r);
    BuildValid(spec);
  }
}

// The half-integral sheet: the documented LP optimum is a consistent solution (the LP
// optimality itself is checked by the sheet LP's tests, which have a solver).
TEST(GridTMeshBuilderTest, HalfIntegerSheetExampleIsConsistent) {
  const HalfIntegerSheetExample example = MakeHalfIntegerSheetExample();
  const GridTMesh mesh = BuildValid(example.spec);
  const v1::TMesh& proto = mesh.proto();
  std::vector<double> q(proto.arcs_size(), 0.0);
  const int root = mesh.ArcBetween(example.root.first, example.root.second);
  ASSERT_GE(root, 0);
  q[root] = 1.0;
  for (const auto& [a, b] : example.half_arcs) {
    const int arc = mesh.ArcBetween(a, b);
    ASSERT_GE(arc, 0);
    q[arc] = 0.5;
  }
  double objective = 0;
  for (double x : q) objective += x;
  EXPECT_EQ(objective, 11.5);
  // The root is a u-side of two patches whose opposite sides are split at u = 1.
  int split_sides = 0;
  for (const v1::Patch& patch : proto.patches()) {
    std::array<double, 6> side_sum = {};
    std::array<int, 6> side_arcs = {};
    bool has_root = false;
    for (const v1::DirectedHalfarcs& side : patch.halfarcs_by_dir()) {
      const int d = DirIndex(*DirFromUpstreamBits(side.dir()));
      for (int h : side.halfarcs()) {
        side_sum[d] += q[h >> 1];
        ++side_arcs[d];
        has_root = has_root || (h >> 1) == root;
      }
    }
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(side_sum[2 * axis], side_sum[2 * axis + 1]);
      if (has_root && side_arcs[2 * axis] + side_arcs[2 * axis + 1] == 3) ++split_sides;
    }
  }
  EXPECT_EQ(split_sides, 2);
}

TEST(GridTMeshBuilderTest, ExtrudesTheSeparationExamples) {
  {
    const GridTMesh mesh = BuildValid(ExtrudeLayout(SeparationExampleA()));
    EXPECT_EQ(mesh.proto().blocks_size(), 6);
    // F becomes a feature arc through the layer; its ends are feature curve ends.
    const v1::Arc& f = ArcBetween(mesh, {1, 2, 0}, {1, 2, 1});
    EXPECT_TRUE(f.feature());
    EXPECT_TRUE(f.critical());
    EXPECT_EQ(f.length(), 1.0);
    for (int w : {0, 1}) {
      EXPECT_TRUE(NodeAt(mesh, {1, 2, w}).feature());
      EXPECT_TRUE(NodeAt(mesh, {1, 2, w}).critical());
    }
    EXPECT_TRUE(mesh.proto().features_present().arcs());
    EXPECT_EQ(ArcBetween(mesh, {0, 0, 0}, {2, 0, 0}).length(), 3.0);  // b0
    EXPECT_EQ(ArcBetween(mesh, {1, 1, 0}, {2, 1, 0}).length(), 0.5);  // g1
    EXPECT_EQ(ArcBetween(mesh, {1, 2, 1}, {3, 2, 1}).length(), 1.5);  // e1
    EXPECT_EQ(ArcBetween(mesh, {2, 0, 0}, {2, 1, 0}).length(), 0.5);  // k
    EXPECT_EQ(mesh.NodeAt({1, 0, 0}), -1);  // no node below I on the bottom boundary
    // T11's longer corridor keeps the layout consistent.
    const GridTMesh longer = BuildValid(ExtrudeLayout(SeparationExampleA(3.0)));
    EXPECT_EQ(ArcBetween(longer, {0, 0, 0}, {2, 0, 0}).length(), 5.5);
    EXPECT_EQ(ArcBetween(longer, {1, 2, 0}, {3, 2, 0}).length(), 4.0);
  }
  for (double t_u : {3.2, 3.0, 2.5, 3.5}) {
    SCOPED_TRACE(t_u);
    const GridLayout2D layout = SeparationExampleB(t_u);
    const GridTMesh mesh = BuildValid(ExtrudeLayout(layout));
    const GridPoint2 f = layout.feature_nodes[0], t = layout.feature_nodes[1];
    EXPECT_TRUE(ArcBetween(mesh, {f[0], f[1], 0}, {f[0], f[1], 1}).feature());
    EXPECT_TRUE(ArcBetween(mesh, {t[0], t[1], 0}, {t[0], t[1], 1}).feature());
    EXPECT_NEAR(mesh.proto().nodes(mesh.NodeAt({t[0], t[1], 0})).position(0), t_u, 1e-12);
  }
  {
    const GridTMesh mesh = BuildValid(ExtrudeLayout(SeparationExampleC()));
    // Convex corners M, P, J, I, C, F, A and concave corners H, K, E, on both caps.
    EXPECT_EQ(EntityCounts(mesh.proto())[0], 20);
    EXPECT_EQ(ArcBetween(mesh, {1, 1, 0}, {1, 1, 1}).singular(), 1);   // H
    EXPECT_EQ(ArcBetween(mesh, {2, 2, 0}, {2, 2, 1}).singular(), -1);  // F
    EXPECT_FALSE(mesh.proto().features_present().nodes());
  }
}

TEST(GridTMeshBuilderTest, ExtrudesFeatureArcsToFeaturePatches) {
  GridLayout2D layout;
  layout.name = "feature_wall";
  layout.blocks = {{{0, 0}, {1, 1}}, {{1, 0}, {2, 1}}};
  layout.feature_arcs = {{{1, 0}, {1, 1}}};
  const GridTMesh mesh = BuildValid(ExtrudeLayout(layout));
  const int wall = mesh.PatchAt({{1, 0, 0}, {1, 1, 1}});
  ASSERT_GE(wall, 0);
  EXPECT_TRUE(mesh.proto().patches(wall).feature());
  EXPECT_TRUE(mesh.proto().patches(wall).critical());
  EXPECT_TRUE(mesh.proto().features_present().patches());
}

TEST(GridTMeshBuilderTest, RejectsInvalidSpecs) {
  const auto rejects = [](const GridTMeshSpec& spec) {
    return BuildGridTMesh(spec).status().code() == absl::StatusCode::kInvalidArgument;
  };
  GridTMeshSpec spec;
  EXPECT_TRUE(rejects(spec));  // no blocks
  spec.blocks = {{{0, 0, 0}, {2, 1, 1}}, {{1, 0, 0}, {3, 1, 1}}};
  EXPECT_TRUE(rejects(spec));  // overlap
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 1, 0}, {2, 2, 1}}};
  EXPECT_TRUE(rejects(spec));  // blocks meeting along an edge only
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 1, 1}, {2, 2, 2}}};
  EXPECT_TRUE(rejects(spec));  // blocks meeting at a corner only
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  spec.feature_nodes = {{0, 0, 1}};
  EXPECT_FALSE(rejects(spec));
  spec.feature_nodes = {{0, 0, 2}};
  EXPECT_TRUE(rejects(spec));  // not a node
  spec.feature_nodes.clear();
  spec.block_rotations = {{0, 24}};
  EXPECT_TRUE(rejects(spec));
  spec.block_rotations = {{1, 0}};
  EXPECT_TRUE(rejects(spec));
  spec.block_rotations.clear();
  spec.spacing[0] = {0.0};
  EXPECT_TRUE(rejects(spec));
}

}  // namespace
}  // namespace ispq::testing
