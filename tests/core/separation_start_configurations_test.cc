// SPDX-License-Identifier: Apache-2.0
#include "core/separation_start_configurations.h"

#include <algorithm>
#include <string>
#include <vector>

#include "core/halfarc_neighborhood.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::GridPoint;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;
using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::ShortName;
using ::ispq::testing::TMeshOrDie;

struct Grid {
  GridTMesh grid;
  TMesh mesh;
};

Grid BuildOrDie(const GridTMeshSpec& spec) {
  absl::StatusOr<GridTMesh> grid = BuildGridTMesh(spec);
  if (!grid.ok()) {
    ADD_FAILURE() << grid.status();
    std::abort();
  }
  TMesh mesh = TMeshOrDie(grid->proto());
  return {*std::move(grid), std::move(mesh)};
}

// Halfarcs as (from point, to point), sorted, to compare sets by geometry.
using Segment = std::pair<GridPoint, GridPoint>;

std::vector<Segment> Segments(const Grid& g, std::span<const HalfarcId> halfarcs) {
  std::vector<Segment> result;
  for (HalfarcId h : halfarcs) {
    result.push_back({g.grid.node_point(g.mesh.tail(h)), g.grid.node_point(g.mesh.head(h))});
  }
  std::sort(result.begin(), result.end());
  return result;
}

std::vector<Segment> ArcSegments(const Grid& g, std::span<const ArcId> arcs) {
  std::vector<Segment> result;
  for (ArcId a : arcs) result.push_back(g.grid.arc_ends(a));
  std::sort(result.begin(), result.end());
  return result;
}

std::vector<int> ConfigsOf(const SeparationStartConfigurations& configs, EntityId e) {
  std::vector<int> result;
  for (int i = 0; i < configs.size(); ++i) {
    if (configs[i].entity == e) result.push_back(i);
  }
  return result;
}

EntityId LinkThrough(const Grid& g, const GridPoint& a, const GridPoint& b) {
  const ArcId arc = g.grid.ArcBetween(a, b);
  for (EntityId e = 0; e < g.mesh.num_entities(); ++e) {
    if (g.mesh.entity_dim(e) != EntityDim::kLink) continue;
    for (HalfarcId h : g.mesh.entity_halfarcs(e)) {
      if (ArcOf(h) == arc) return e;
    }
  }
  return kNoId;
}

// Single cube: a sector per outgoing halfarc of each corner, and per face at each edge link;
// a link sector may leave the link at either end, into its face.
TEST(SeparationStartConfigurationsTest, SingleCube) {
  const TMesh cube = LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const SeparationStartConfigurations configs(cube);
  ASSERT_EQ(configs.size(), 8 * 3 + 12 * 2);
  for (int i = 0; i < configs.size(); ++i) {
    const SeparationStartConfiguration& c = configs[i];
    EXPECT_EQ(c.start_block, 0);
    EXPECT_FALSE(c.cyclic_link);
    if (!c.is_link) {
      EXPECT_EQ(cube.entity_dim(c.entity), EntityDim::kNode);
      EXPECT_EQ(configs.branch_offs(i).size(), 1u);
      EXPECT_EQ(configs.branch_offs(i)[0], cube.outgoing_halfarcs(c.start_node)[c.sector]);
      EXPECT_TRUE(configs.pre_branch_arcs(i).empty());
      EXPECT_EQ(configs.link_axis(i), 0);
      continue;
    }
    const HalfarcId link = cube.entity_halfarcs(c.entity)[0];
    EXPECT_EQ(c.start_node, cube.tail(link));
    EXPECT_EQ(c.link_dir, *cube.HalfarcDirInBlock(link, 0));
    EXPECT_EQ(configs.link_axis(i), AxisBits(AxisOf(c.link_dir)));
    ASSERT_EQ(configs.pre_branch_arcs(i).size(), 1u);
    EXPECT_EQ(configs.pre_branch_arcs(i)[0], ArcOf(link));
    // Sector k leaves through the face of the k-th halfpatch around the link, at both ends.
    const HalfpatchId face = HalfpatchesAroundHalfarc(cube, link)[c.sector];
    const std::span<const HalfarcId> offs = configs.branch_offs(i);
    ASSERT_EQ(offs.size(), 2u);
    std::vector<NodeId> tails = {cube.tail(offs[0]), cube.tail(offs[1])};
    std::vector<NodeId> ends = {cube.tail(link), cube.head(link)};
    std::sort(tails.begin(), tails.end());
    std::sort(ends.begin(), ends.end());
    EXPECT_EQ(tails, ends);
    for (HalfarcId h : offs) {
      EXPECT_NE(AxisOf(*cube.HalfarcDirInBlock(h, 0)), AxisOf(c.link_dir));
      EXPECT_EQ(*cube.HalfarcDirInBlock(h, 0), *cube.HalfarcDirInBlock(offs[0], 0));
      // The halfarc or its twin bounds the sector's face.
      EXPECT_TRUE(IndexInHalfpatchCycle(cube, face, h) >= 0 ||
                  IndexInHalfpatchCycle(cube, face, Twin(h)) >= 0);
    }
  }
}

// T7: the u-edge link at v = 0, w = 0 of two blocks along u. Its bottom sector may branch into
// the bottom wall at u = 0, 1 and 2, its front sector into the front wall; PreArcs is the first
// link arc only, since the second link arc starts a new patch side.
TEST(SeparationStartConfigurationsTest, LinkAlongTwoBlocks) {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
  const Grid g = BuildOrDie(spec);
  const SeparationStartConfigurations configs(g.mesh);
  const EntityId link = LinkThrough(g, {0, 0, 0}, {1, 0, 0});
  ASSERT_NE(link, kNoId);
  ASSERT_EQ(g.mesh.entity_halfarcs(link).size(), 2u);
  const std::vector<int> sectors = ConfigsOf(configs, link);
  ASSERT_EQ(sectors.size(), 2u);
  std::vector<std::vector<Segment>> branch_offs;
  for (int i : sectors) {
    branch_offs.push_back(Segments(g, configs.branch_offs(i)));
    EXPECT_EQ(ArcSegments(g, configs.pre_branch_arcs(i)),
              ArcSegments(g, std::vector<ArcId>{ArcOf(g.mesh.entity_halfarcs(link)[0])}));
  }
  std::sort(branch_offs.begin(), branch_offs.end());
  const std::vector<Segment> bottom = {
      {{0, 0, 0}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}}, {{2, 0, 0}, {2, 1, 0}}};
  const std::vector<Segment> front = {
      {{0, 0, 0}, {0, 0, 1}}, {{1, 0, 0}, {1, 0, 1}}, {{2, 0, 0}, {2, 0, 1}}};
  EXPECT_EQ(branch_offs, (std::vector<std::vector<Segment>>{front, bottom}));
}

// A one-arc feature link whose first node lies inside a patch side: in the big block's front
// face the link continues a collinear run, so that sector's first branch-off sits at the corner
// before the run and the collinear arc joins PreArcs (shared by every sector of the link).
TEST(SeparationStartConfigurationsTest, LinkInsideAPatchSide) {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {2, 1, 1}}, {{0, 0, 1}, {1, 1, 2}}, {{1, 0, 1}, {2, 1, 2}}};
  spec.feature_arcs = {{{1, 0, 1}, {2, 0, 1}}};
  const Grid g = BuildOrDie(spec);
  const SeparationStartConfigurations configs(g.mesh);
  const EntityId link = LinkThrough(g, {1, 0, 1}, {2, 0, 1});
  ASSERT_NE(link, kNoId);
  ASSERT_EQ(g.mesh.entity_halfarcs(link).size(), 1u);
  const std::vector<int> sectors = ConfigsOf(configs, link);
  ASSERT_EQ(sectors.size(), 3u);  // the big block's front face, the upper block's, the interface
  std::vector<std::vector<Segment>> branch_offs;
  for (int i : sectors) {
    branch_offs.push_back(Segments(g, configs.branch_offs(i)));
    EXPECT_EQ(ArcSegments(g, configs.pre_branch_arcs(i)),
              (std::vector<Segment>{{{0, 0, 1}, {1, 0, 1}}, {{1, 0, 1}, {2, 0, 1}}}));
  }
  std::sort(branch_offs.begin(), branch_offs.end());
  const std::vector<Segment> big_front = {{{0, 0, 1}, {0, 0, 0}}, {{2, 0, 1}, {2, 0, 0}}};
  const std::vector<Segment> upper_front = {{{1, 0, 1}, {1, 0, 2}}, {{2, 0, 1}, {2, 0, 2}}};
  const std::vector<Segment> interface = {{{1, 0, 1}, {1, 1, 1}}, {{2, 0, 1}, {2, 1, 1}}};
  std::vector<std::vector<Segment>> expected = {big_front, upper_front, interface};
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(branch_offs, expected);
}

// On real data: every critical node has one configuration per outgoing halfarc, every link one
// per halfpatch around its first halfarc; branch-offs leave the link axis, start on the link's
// line and are distinct; PreArcs contains the first link arc.
TEST(SeparationStartConfigurationsTest, RealMeshes) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    const SeparationStartConfigurations configs(mesh);
    int expected = 0;
    for (EntityId e = 0; e < mesh.num_entities(); ++e) {
      if (mesh.entity_dim(e) == EntityDim::kNode) {
        expected += static_cast<int>(mesh.outgoing_halfarcs(mesh.entity_node_from(e)).size());
      } else if (mesh.entity_dim(e) == EntityDim::kLink) {
        expected +=
            static_cast<int>(mesh.arc_halfpatches(ArcOf(mesh.entity_halfarcs(e)[0])).size());
      }
    }
    ASSERT_EQ(configs.size(), expected);
    for (int i = 0; i < configs.size(); ++i) {
      const SeparationStartConfiguration& c = configs[i];
      if (!c.is_link) continue;
      const HalfarcId first = mesh.entity_halfarcs(c.entity)[0];
      EXPECT_EQ(c.start_block, BlocksAroundHalfarc(mesh, first)[0]);
      const std::span<const ArcId> pre = configs.pre_branch_arcs(i);
      EXPECT_TRUE(std::binary_search(pre.begin(), pre.end(), ArcOf(first)));
      std::vector<HalfarcId> offs(configs.branch_offs(i).begin(), configs.branch_offs(i).end());
      ASSERT_FALSE(offs.empty());
      std::sort(offs.begin(), offs.end());
      EXPECT_EQ(std::adjacent_find(offs.begin(), offs.end()), offs.end());
      for (HalfarcId h : offs) {
        EXPECT_FALSE(std::binary_search(pre.begin(), pre.end(), ArcOf(h)));
      }
    }
  }
}

}  // namespace
}  // namespace ispq
