// SPDX-License-Identifier: Apache-2.0
#include "core/critical_entities.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "core/tmesh.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "ispq/v1/tmesh.pb.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::GridPoint;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;
using ::testing::UnorderedElementsAre;

// The entity list a file carries, in the derived form (regions compare no nodes).
std::vector<CriticalEntity> ListedEntities(const v1::TMesh& proto) {
  std::vector<CriticalEntity> entities;
  for (const v1::CriticalEntity& listed : proto.critical_entities()) {
    CriticalEntity& e = entities.emplace_back();
    e.dim = static_cast<EntityDim>(listed.dim());
    if (e.dim != EntityDim::kRegion) {
      e.node_from = listed.node_from();
      e.node_to = listed.node_to();
    }
    e.halfarcs.assign(listed.halfarcs().begin(), listed.halfarcs().end());
    e.patches.assign(listed.patches().begin(), listed.patches().end());
    e.boundary_arcs.assign(listed.boundary_arcs().begin(), listed.boundary_arcs().end());
  }
  return entities;
}

// Whatever the mesh: links are chains of critical arcs through non-critical nodes that cover
// every critical arc once, and regions partition the critical patches.
void ExpectEntitiesPartitionTheCriticalElements(const TMesh& mesh,
                                                const std::vector<CriticalEntity>& entities) {
  std::vector<int> arc_uses(mesh.num_arcs(), 0), patch_uses(mesh.num_patches(), 0);
  int nodes = 0;
  for (const CriticalEntity& e : entities) {
    switch (e.dim) {
      case EntityDim::kNode:
        EXPECT_TRUE(mesh.node_critical(e.node_from));
        EXPECT_EQ(e.node_to, e.node_from);
        ++nodes;
        break;
      case EntityDim::kLink:
        ASSERT_FALSE(e.halfarcs.empty());
        EXPECT_EQ(mesh.tail(e.halfarcs.front()), e.node_from);
        EXPECT_EQ(mesh.head(e.halfarcs.back()), e.node_to);
        for (size_t i = 0; i < e.halfarcs.size(); ++i) {
          EXPECT_TRUE(mesh.arc_critical(ArcOf(e.halfarcs[i])));
          ++arc_uses[ArcOf(e.halfarcs[i])];
          if (i + 1 < e.halfarcs.size()) {
            const NodeId inner = mesh.head(e.halfarcs[i]);
            EXPECT_EQ(inner, mesh.tail(e.halfarcs[i + 1]));
            EXPECT_FALSE(mesh.node_critical(inner)) << DescribeCriticalEntity(e);
          }
        }
        break;
      case EntityDim::kRegion:
        for (PatchId p : e.patches) {
          EXPECT_TRUE(mesh.patch_critical(p));
          ++patch_uses[p];
        }
        for (ArcId a : e.boundary_arcs) EXPECT_TRUE(mesh.arc_critical(a));
        break;
    }
  }
  int critical_nodes = 0;
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) critical_nodes += mesh.node_critical(n) ? 1 : 0;
  EXPECT_EQ(nodes, critical_nodes);
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    EXPECT_EQ(arc_uses[a], mesh.arc_critical(a) ? 1 : 0) << "arc " << a;
  }
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    EXPECT_EQ(patch_uses[p], mesh.patch_critical(p) ? 1 : 0) << "patch " << p;
  }
}

// Two unit blocks along u: the wall between them is flat boundary, so the four long edges are
// links through a non-critical wall node and the four long sides are regions of two patches.
TEST(CriticalEntitiesTest, TwoBlocksMakeLinksThroughWallNodesAndTwoPatchRegions) {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
  const GridTMesh grid = testing::BuildGridTMeshOrDie(spec);
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  const std::vector<CriticalEntity> entities = DeriveCriticalEntities(mesh);
  ASSERT_EQ(entities.size(), 8u + 12u + 6u);
  ExpectEntitiesPartitionTheCriticalElements(mesh, entities);
  // Nodes first, ascending.
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(entities[i].dim, EntityDim::kNode);
    if (i > 0) {
      EXPECT_LT(entities[i - 1].node_from, entities[i].node_from);
    }
  }
  // The link along the edge v = w = 0 runs from one corner to the other through (1, 0, 0).
  const std::vector<int> edge = grid.HalfarcChain({0, 0, 0}, {2, 0, 0});
  const std::vector<int> reversed_edge = grid.HalfarcChain({2, 0, 0}, {0, 0, 0});
  ASSERT_EQ(edge.size(), 2u);
  int edge_links = 0;
  for (const CriticalEntity& e : entities) {
    if (e.dim != EntityDim::kLink) continue;
    if (e.halfarcs == edge || e.halfarcs == reversed_edge) ++edge_links;
    // The four long edges pass a wall node; the others are single arcs.
    const bool long_edge = grid.node_point(e.node_from)[0] != grid.node_point(e.node_to)[0];
    EXPECT_EQ(e.halfarcs.size(), long_edge ? 2u : 1u) << DescribeCriticalEntity(e);
  }
  EXPECT_EQ(edge_links, 1);
  // The bottom side w = 0: two patches bounded by the six arcs of its rim, not the wall arc.
  const int left = grid.PatchAt({{0, 0, 0}, {1, 1, 0}});
  const int right = grid.PatchAt({{1, 0, 0}, {2, 1, 0}});
  std::vector<ArcId> rim = {
      grid.ArcBetween({0, 0, 0}, {1, 0, 0}), grid.ArcBetween({1, 0, 0}, {2, 0, 0}),
      grid.ArcBetween({0, 1, 0}, {1, 1, 0}), grid.ArcBetween({1, 1, 0}, {2, 1, 0}),
      grid.ArcBetween({0, 0, 0}, {0, 1, 0}), grid.ArcBetween({2, 0, 0}, {2, 1, 0})};
  std::sort(rim.begin(), rim.end());
  int bottoms = 0;
  std::vector<size_t> region_sizes;
  for (const CriticalEntity& e : entities) {
    if (e.dim != EntityDim::kRegion) continue;
    region_sizes.push_back(e.patches.size());
    if (e.patches == std::vector<PatchId>{std::min(left, right), std::max(left, right)}) {
      ++bottoms;
      EXPECT_EQ(e.boundary_arcs, rim);
    }
  }
  EXPECT_EQ(bottoms, 1);
  EXPECT_THAT(region_sizes, UnorderedElementsAre(1, 1, 2, 2, 2, 2));
  // And it is exactly the list the grid builder wrote by the format's rules.
  EXPECT_EQ(entities, ListedEntities(grid.proto()));
}

// A closed loop of interior feature arcs through non-critical nodes is a cyclic link, started
// at its lowest arc and ending where it started.
TEST(CriticalEntitiesTest, ALoopOfFeatureArcsWithoutCriticalNodesIsACyclicLink) {
  GridTMeshSpec spec;
  for (int w = 0; w < 2; ++w) {
    for (int v = 0; v < 3; ++v) {
      for (int u = 0; u < 3; ++u) spec.blocks.push_back({{u, v, w}, {u + 1, v + 1, w + 1}});
    }
  }
  const GridPoint a = {1, 1, 1}, b = {2, 1, 1}, c = {2, 2, 1}, d = {1, 2, 1};
  spec.feature_arcs = {{a, b}, {b, c}, {d, c}, {a, d}};
  const GridTMesh grid = testing::BuildGridTMeshOrDie(spec);
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  for (const GridPoint& p : {a, b, c, d}) EXPECT_FALSE(mesh.node_critical(grid.NodeAt(p)));
  const std::vector<CriticalEntity> entities = DeriveCriticalEntities(mesh);
  ExpectEntitiesPartitionTheCriticalElements(mesh, entities);
  std::vector<ArcId> loop = {grid.ArcBetween(a, b), grid.ArcBetween(b, c), grid.ArcBetween(c, d),
                             grid.ArcBetween(d, a)};
  const ArcId lowest = *std::min_element(loop.begin(), loop.end());
  std::vector<const CriticalEntity*> cycles;
  for (const CriticalEntity& e : entities) {
    if (e.dim == EntityDim::kLink && e.node_from == e.node_to) cycles.push_back(&e);
  }
  ASSERT_EQ(cycles.size(), 1u);
  const CriticalEntity& cycle = *cycles[0];
  ASSERT_EQ(cycle.halfarcs.size(), 4u);
  EXPECT_EQ(cycle.halfarcs[0], HalfarcOf(lowest, false));
  EXPECT_EQ(cycle.node_from, mesh.tail(HalfarcOf(lowest, false)));
  std::vector<ArcId> cycle_arcs;
  for (HalfarcId h : cycle.halfarcs) cycle_arcs.push_back(ArcOf(h));
  EXPECT_THAT(cycle_arcs, UnorderedElementsAre(loop[0], loop[1], loop[2], loop[3]));
  // Cycles come after the links that start at critical nodes.
  EXPECT_EQ(cycles[0], &entities[entities.size() - 7]);  // then the cube's six regions
  EXPECT_EQ(entities, ListedEntities(grid.proto()));
}

// On real meshes the derived list is the exporter's list (the loader's check relies on it) and
// partitions the critical elements.
TEST(CriticalEntitiesTest, RealMeshesGetTheirExportedLists) {
  for (const char* file :
       {"hex-me/s01c_cube.tmesh.json", "singularity-constrained-fields/sphere.tmesh.json",
        "singularity-constrained-fields/prisma.tmesh.json"}) {
    SCOPED_TRACE(file);
    const v1::TMesh proto = testing::LoadProtoOrDie(testing::RealTMeshPath(file));
    const TMesh mesh = testing::TMeshOrDie(proto);
    const std::vector<CriticalEntity> entities = DeriveCriticalEntities(mesh);
    EXPECT_EQ(entities, ListedEntities(proto));
    ExpectEntitiesPartitionTheCriticalElements(mesh, entities);
  }
}

TEST(CriticalEntitiesTest, DescriptionsNameTheEntity) {
  CriticalEntity node;
  node.node_from = node.node_to = 4;
  EXPECT_EQ(DescribeCriticalEntity(node), "node 4");
  CriticalEntity link;
  link.dim = EntityDim::kLink;
  link.node_from = 3;
  link.node_to = 7;
  link.halfarcs = {6, 9};
  EXPECT_EQ(DescribeCriticalEntity(link), "link 3->7 [halfarcs 6,9]");
  CriticalEntity region;
  region.dim = EntityDim::kRegion;
  region.patches = {2, 5};
  region.boundary_arcs = {1};
  EXPECT_EQ(DescribeCriticalEntity(region), "region [patches 2,5; boundary arcs 1]");
}

}  // namespace
}  // namespace ispq
