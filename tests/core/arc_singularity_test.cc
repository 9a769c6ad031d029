// SPDX-License-Identifier: Apache-2.0
#include "core/arc_singularity.h"

#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "core/tmesh.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::GridPoint;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;

struct Example {
  GridTMesh grid;
  TMesh mesh;
};

Example Build(const GridTMeshSpec& spec) {
  absl::StatusOr<GridTMesh> grid = BuildGridTMesh(spec);
  EXPECT_TRUE(grid.ok()) << grid.status();
  TMesh mesh = testing::TMeshOrDie(grid->proto());
  return {*std::move(grid), std::move(mesh)};
}

struct ExpectedArc {
  GridPoint from, to;
  int quarter_turns;
  bool on_boundary;
  bool singular;
};

void ExpectArcs(const Example& example, const std::vector<ExpectedArc>& expected) {
  const std::vector<int> turns = QuarterTurnsAroundArcs(example.mesh);
  ASSERT_EQ(static_cast<int>(turns.size()), example.mesh.num_arcs());
  for (const ExpectedArc& e : expected) {
    const int a = example.grid.ArcBetween(e.from, e.to);
    ASSERT_GE(a, 0);
    SCOPED_TRACE(a);
    EXPECT_EQ(turns[a], e.quarter_turns);
    EXPECT_EQ(ArcOnBoundary(example.mesh, a), e.on_boundary);
    EXPECT_EQ(SingularByQuarterTurns(turns[a], e.on_boundary), e.singular);
  }
  // The builder marks singular arcs by the format's rule; the count must agree on every arc.
  for (ArcId a = 0; a < example.mesh.num_arcs(); ++a) {
    EXPECT_EQ(SingularByQuarterTurns(turns[a], ArcOnBoundary(example.mesh, a)),
              example.mesh.arc_singular(a) != 0)
        << "arc " << a;
  }
}

// A block next to a taller one: convex edges (1 quarter turn), a concave edge where the low
// block's top meets the tall block's side (a face half turn plus an edge, 3), and flat boundary
// where the two blocks' edges meet side by side (2).
TEST(ArcSingularityTest, StepHasConvexConcaveAndFlatBoundaryArcs) {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 2}}, {{1, 0, 0}, {2, 1, 1}}};
  const Example step = Build(spec);
  ExpectArcs(step, {
                       {{0, 0, 0}, {1, 0, 0}, 1, true, true},   // convex edge of the tall block
                       {{1, 0, 1}, {1, 1, 1}, 3, true, true},   // the concave edge
                       {{1, 0, 0}, {1, 1, 0}, 2, true, false},  // flat, on the bottom
                       {{1, 0, 0}, {1, 0, 1}, 2, true, false},  // flat, on the front side
                       {{1, 0, 1}, {1, 0, 2}, 1, true, true},   // the tall block's edge above
                   });
}

// Interior arcs: four blocks around an edge, or two blocks' edges and one block's face (a
// T-junction) make a full turn and are regular.
TEST(ArcSingularityTest, InteriorArcsOfAFullTurnAreRegular) {
  GridTMeshSpec grid;
  for (int w = 0; w < 2; ++w) {
    for (int v = 0; v < 2; ++v) {
      for (int u = 0; u < 2; ++u) grid.blocks.push_back({{u, v, w}, {u + 1, v + 1, w + 1}});
    }
  }
  ExpectArcs(Build(grid), {
                              {{1, 1, 0}, {1, 1, 1}, 4, false, false},
                              {{0, 1, 1}, {1, 1, 1}, 4, false, false},
                              {{1, 0, 0}, {1, 1, 0}, 2, true, false},
                              {{0, 0, 0}, {1, 0, 0}, 1, true, true},
                          });
  GridTMeshSpec t_junction;
  t_junction.blocks = {{{0, 0, 0}, {1, 2, 2}}, {{1, 0, 0}, {2, 1, 2}}, {{1, 1, 0}, {2, 2, 2}}};
  ExpectArcs(Build(t_junction), {
                                    {{1, 1, 0}, {1, 1, 2}, 4, false, false},
                                    {{1, 1, 0}, {2, 1, 0}, 2, true, false},
                                });
}

TEST(ArcSingularityTest, RegularTurnsDependOnTheBoundary) {
  EXPECT_FALSE(SingularByQuarterTurns(4, false));
  EXPECT_TRUE(SingularByQuarterTurns(3, false));
  EXPECT_TRUE(SingularByQuarterTurns(5, false));
  EXPECT_FALSE(SingularByQuarterTurns(2, true));
  EXPECT_TRUE(SingularByQuarterTurns(1, true));
  EXPECT_TRUE(SingularByQuarterTurns(3, true));
  EXPECT_TRUE(SingularByQuarterTurns(4, true));
}

// On real meshes the counted turns reproduce which arcs the exporter marked singular, including
// interior singular arcs (3 or 5 quarter turns), which grid meshes cannot have.
TEST(ArcSingularityTest, RealMeshesAgreeWithTheirSingularMarks) {
  int interior_singular = 0;
  for (const char* file :
       {"singularity-constrained-fields/sphere.tmesh.json",
        "singularity-constrained-fields/prisma.tmesh.json", "hex-me/s01c_cube.tmesh.json"}) {
    SCOPED_TRACE(file);
    const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath(file));
    const std::vector<int> turns = QuarterTurnsAroundArcs(mesh);
    for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
      const bool boundary = ArcOnBoundary(mesh, a);
      EXPECT_EQ(SingularByQuarterTurns(turns[a], boundary), mesh.arc_singular(a) != 0) << a;
      if (!boundary && turns[a] != 4) ++interior_singular;
    }
  }
  EXPECT_GT(interior_singular, 0);
}

}  // namespace
}  // namespace ispq
