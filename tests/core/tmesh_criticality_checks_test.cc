// SPDX-License-Identifier: Apache-2.0
// The criticality rules on small grid meshes whose flags the grid builder derives on its own:
// every built mesh passes; node types and critical-entity lists that differ from what the mesh
// makes are named; a node made critical only by feature arcs or feature patches is reported once
// the source claims to have none of them; and arc flags that contradict the blocks around the arc
// are refused. A TMesh with wrong flags cannot exist, so the arc-flag cases go through
// TMeshFromProto (whose own table, tests/core/proto/tmesh_from_proto_test.cc, covers the real
// files); the other checks take what they compare as arguments and are called directly.
#include "core/tmesh_criticality_checks.h"

#include <string>
#include <utility>
#include <vector>

#include "core/critical_entities.h"
#include "core/proto/tmesh_from_proto.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using testing::GridPoint;
using testing::GridTMesh;
using testing::GridTMeshSpec;
using ::testing::HasSubstr;

constexpr FeaturesPresent kAllFeatures = {.nodes = true, .arcs = true, .patches = true};

// Two unit blocks side by side along u; their shared wall is u = 1.
GridTMeshSpec TwoBlocks() {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
  return spec;
}

// Four unit blocks around the interior arc from (1,1,0) to (1,1,1).
GridTMeshSpec FourBlocksAroundAnArc() {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}},
                 {{1, 0, 0}, {2, 1, 1}},
                 {{0, 1, 0}, {1, 2, 1}},
                 {{1, 1, 0}, {2, 2, 1}}};
  return spec;
}

// Node (1,0,0) on the wall's bottom edge: two singular (box edge) arcs along u, which are not
// feature arcs, and the two wall arcs along v and w marked feature. Critical only by the rule
// "two feature arcs and a non-feature singular arc" (SEMI_FEATURE_SINGULAR_BRANCH).
GridTMeshSpec FeatureArcsAtAWallCorner() {
  GridTMeshSpec spec = TwoBlocks();
  spec.feature_arcs = {{{1, 0, 0}, {1, 1, 0}}, {{1, 0, 0}, {1, 0, 1}}};
  return spec;
}

// The wall itself a feature patch: node (1,0,0) has no feature arc, two singular arcs off the
// feature patch, and lies on it. Critical only by the feature-patch rule.
GridTMeshSpec FeatureWall() {
  GridTMeshSpec spec = TwoBlocks();
  spec.feature_patches = {{{1, 0, 0}, {1, 1, 1}}};
  return spec;
}

std::vector<NodeTypes> DeclaredTypes(const v1::TMesh& proto) {
  std::vector<NodeTypes> types;
  for (const v1::Node& node : proto.nodes()) {
    types.push_back({static_cast<SingularType>(node.singular_type()),
                     static_cast<FeatureType>(node.feature_type())});
  }
  return types;
}

TEST(TMeshCriticalityChecksTest, BuiltMeshesPass) {
  for (const GridTMeshSpec& spec :
       {TwoBlocks(), FourBlocksAroundAnArc(), FeatureArcsAtAWallCorner(), FeatureWall()}) {
    const GridTMesh grid = testing::BuildGridTMeshOrDie(spec);
    const TMesh mesh = testing::TMeshOrDie(grid.proto());
    EXPECT_TRUE(CheckArcSingularity(mesh).ok());
    EXPECT_TRUE(CheckCriticalNodes(mesh, kAllFeatures).ok());
    EXPECT_TRUE(CheckNodeTypes(mesh, DeclaredTypes(grid.proto())).ok());
    const std::vector<CriticalEntity> derived = DeriveCriticalEntities(mesh);
    EXPECT_TRUE(CheckListedCriticalEntities(derived, derived).ok());
  }
}

// present.arcs decides whether the feature-arc rules count: a node critical only through them
// contradicts its flag once the source says it has no feature arcs.
TEST(TMeshCriticalityChecksTest, FeatureArcRulesApplyOnlyWhenTheSourceHasFeatureArcs) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(FeatureArcsAtAWallCorner());
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  const NodeId corner = grid.NodeAt({1, 0, 0});
  ASSERT_TRUE(mesh.node_critical(corner));
  ASSERT_FALSE(mesh.node_feature(corner));
  EXPECT_EQ(CheckCriticalNodes(mesh, {.nodes = true, .arcs = false, .patches = true}).message(),
            "node " + std::to_string(corner) +
                ": critical flag 1 contradicts the criticality rules (2 singular and 2 feature "
                "arcs)");
  std::vector<NodeTypes> types = DeclaredTypes(grid.proto());
  EXPECT_EQ(types[corner].feature, FeatureType::kSemiFeatureSingularBranch);
}

TEST(TMeshCriticalityChecksTest, FeaturePatchRuleAppliesOnlyWhenTheSourceHasFeaturePatches) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(FeatureWall());
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  const NodeId corner = grid.NodeAt({1, 0, 0});
  ASSERT_TRUE(mesh.node_critical(corner));
  const absl::Status status =
      CheckCriticalNodes(mesh, {.nodes = true, .arcs = true, .patches = false});
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()),
              HasSubstr("node " + std::to_string(corner) + ": critical flag 1 contradicts"));
  EXPECT_EQ(DeclaredTypes(grid.proto())[corner].feature, FeatureType::kSemiFeatureSingularBranch);
}

TEST(TMeshCriticalityChecksTest, NodeTypesThatDifferFromTheMarksAreNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(FeatureArcsAtAWallCorner());
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  const NodeId corner = grid.NodeAt({1, 0, 0});
  const NodeId box_corner = grid.NodeAt({0, 0, 0});

  std::vector<NodeTypes> types = DeclaredTypes(grid.proto());
  ASSERT_EQ(types[corner].singular, SingularType::kSemiSingular);
  types[corner].singular = SingularType::kSingular;
  EXPECT_EQ(CheckNodeTypes(mesh, types).message(),
            "node " + std::to_string(corner) +
                ": singularType SINGULAR but 2 singular arcs meet there (SEMI_SINGULAR)");

  types = DeclaredTypes(grid.proto());
  types[box_corner].singular = SingularType::kRegular;
  EXPECT_EQ(CheckNodeTypes(mesh, types).message(),
            "node " + std::to_string(box_corner) +
                ": singularType REGULAR but 3 singular arcs meet there (SINGULAR)");

  types = DeclaredTypes(grid.proto());
  types[corner].feature = FeatureType::kSemiFeature;
  EXPECT_EQ(CheckNodeTypes(mesh, types).message(),
            "node " + std::to_string(corner) +
                ": featureType SEMI_FEATURE but its marks make it SEMI_FEATURE_SINGULAR_BRANCH (2 "
                "feature and 2 singular arcs, not a feature node)");

  // The far end of a feature arc is a feature node (one feature arc): FEATURE.
  const NodeId end = grid.NodeAt({1, 1, 0});
  ASSERT_TRUE(mesh.node_feature(end));
  types = DeclaredTypes(grid.proto());
  ASSERT_EQ(types[end].feature, FeatureType::kFeature);
  types[end].feature = FeatureType::kRegular;
  EXPECT_THAT(std::string(CheckNodeTypes(mesh, types).message()),
              HasSubstr("node " + std::to_string(end) +
                        ": featureType REGULAR but its marks make it FEATURE"));
  EXPECT_THAT(std::string(CheckNodeTypes(mesh, types).message()), HasSubstr("a feature node)"));
}

TEST(TMeshCriticalityChecksTest, AListedEntityListMustBeTheDerivedOne) {
  const TMesh mesh = testing::TMeshOrDie(testing::BuildGridTMeshOrDie(TwoBlocks()).proto());
  const std::vector<CriticalEntity> derived = DeriveCriticalEntities(mesh);
  ASSERT_GE(derived.size(), 3u);
  // An empty list is "none sent": nothing to compare.
  EXPECT_TRUE(CheckListedCriticalEntities(derived, {}).ok());

  std::vector<CriticalEntity> swapped = derived;
  std::swap(swapped[1], swapped[2]);
  EXPECT_EQ(CheckListedCriticalEntities(derived, swapped).message(),
            "critical entity 1: the mesh makes it " + DescribeCriticalEntity(derived[1]) +
                ", the request says " + DescribeCriticalEntity(derived[2]));

  std::vector<CriticalEntity> longer = derived;
  longer.push_back(derived[0]);
  EXPECT_EQ(CheckListedCriticalEntities(derived, longer).message(),
            "critical entity " + std::to_string(derived.size()) + ": the mesh has only " +
                std::to_string(derived.size()) + " critical entities, the request lists " +
                std::to_string(longer.size()));

  const std::vector<CriticalEntity> shorter(derived.begin(), derived.end() - 1);
  EXPECT_EQ(CheckListedCriticalEntities(derived, shorter).message(),
            "critical entity " + std::to_string(shorter.size()) +
                ": missing from the request (the mesh makes it " +
                DescribeCriticalEntity(derived.back()) + ")");
}

std::string LoadError(const v1::TMesh& proto) {
  const absl::StatusOr<TMesh> mesh = TMeshFromProto(proto);
  EXPECT_FALSE(mesh.ok());
  return std::string(mesh.status().message());
}

TEST(TMeshCriticalityChecksTest, ArcFlagsContradictingTheBlocksAroundAreNamed) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(FourBlocksAroundAnArc());
  // Interior, four blocks around: regular.
  const int interior = grid.ArcBetween({1, 1, 0}, {1, 1, 1});
  // On the boundary between two blocks: regular. On a box edge, one block: singular.
  const int flat = grid.ArcBetween({1, 0, 0}, {1, 0, 1});
  const int edge = grid.ArcBetween({0, 0, 0}, {0, 0, 1});
  ASSERT_EQ(grid.proto().arcs(interior).singular(), 0);
  ASSERT_EQ(grid.proto().arcs(flat).singular(), 0);
  ASSERT_NE(grid.proto().arcs(edge).singular(), 0);

  v1::TMesh marked = grid.proto();
  marked.mutable_arcs(interior)->set_singular(1);
  marked.mutable_arcs(interior)->set_critical(true);
  EXPECT_EQ(LoadError(marked), "arc " + std::to_string(interior) +
                                   ": singular mark 1 contradicts the 4 quarter turns of the "
                                   "blocks around this interior arc (singular iff not 4)");

  v1::TMesh flat_marked = grid.proto();
  flat_marked.mutable_arcs(flat)->set_singular(-1);
  flat_marked.mutable_arcs(flat)->set_critical(true);
  EXPECT_EQ(LoadError(flat_marked), "arc " + std::to_string(flat) +
                                        ": singular mark -1 contradicts the 2 quarter turns of "
                                        "the blocks around this boundary arc (singular iff not 2)");

  v1::TMesh unmarked = grid.proto();
  unmarked.mutable_arcs(edge)->set_singular(0);
  unmarked.mutable_arcs(edge)->set_critical(false);
  EXPECT_THAT(LoadError(unmarked), HasSubstr("arc " + std::to_string(edge) +
                                             ": singular mark 0 contradicts the 1 quarter turns"));

  v1::TMesh off_boundary = grid.proto();
  off_boundary.mutable_arcs(flat)->set_boundary(false);
  EXPECT_EQ(LoadError(off_boundary),
            "arc " + std::to_string(flat) + ": boundary flag 0 but it lies on a boundary patch");
}

}  // namespace
}  // namespace ispq
