// SPDX-License-Identifier: Apache-2.0
// Node potentials: on parts with global frames and no handle, the consistent q are exactly the
// potential differences; frames turned by a singular arc, or a handle, give none.
#include "core/bundle_potentials.h"

#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using testing::GridBox;
using testing::GridTMesh;
using testing::GridTMeshSpec;

std::optional<BundlePotentials> PotentialsOf(const TMesh& mesh) {
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  return BundlePotentials::Compute(mesh, consistency, bundles);
}

// An L of three blocks with a T-junction: the lower row has two blocks under one long block.
GridTMeshSpec LShape() {
  GridTMeshSpec spec;
  spec.blocks = {GridBox{{0, 0, 0}, {1, 1, 1}}, GridBox{{1, 0, 0}, {2, 1, 1}},
                 GridBox{{0, 1, 0}, {2, 2, 1}}, GridBox{{0, 0, 1}, {1, 2, 2}}};
  return spec;
}

TEST(BundlePotentialsTest, ConsistentQuantizationsAreExactlyPotentialDifferences) {
  const GridTMesh grid = testing::BuildGridTMeshOrDie(LShape());
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const std::optional<BundlePotentials> potentials =
      BundlePotentials::Compute(mesh, consistency, bundles);
  ASSERT_TRUE(potentials.has_value());
  // One potential per grid coordinate of each axis: 3 + 3 + 3.
  EXPECT_EQ(potentials->num_potentials(), 9);

  std::mt19937 random(7);
  std::uniform_int_distribution<int64_t> length(0, 5);
  for (int trial = 0; trial < 20; ++trial) {
    // Every consistent q (all of them come from grid intervals here) is a difference: each
    // bundle's q equals U[head] - U[tail] for one U.
    std::array<std::vector<int64_t>, 3> intervals;
    for (auto& axis : intervals) axis = {length(random), length(random)};
    const std::vector<int64_t> q = grid.QFromIntervals(intervals);
    std::vector<int64_t> u(potentials->num_potentials(), 0);
    std::vector<uint8_t> known(potentials->num_potentials(), 0);
    for (bool changed = true; changed;) {
      changed = false;
      for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
        const int64_t value = q[bundles.arcs(b).front()];
        const int32_t t = potentials->tail(b), h = potentials->head(b);
        if (!known[t] && !known[h]) {
          known[t] = 1;
          changed = true;
        }
        if (known[t] && !known[h]) {
          u[h] = u[t] + value;
          known[h] = changed = true;
        } else if (known[h] && !known[t]) {
          u[t] = u[h] - value;
          known[t] = changed = true;
        }
      }
    }
    for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
      for (const ArcId a : bundles.arcs(b)) {
        EXPECT_EQ(q[a], u[potentials->head(b)] - u[potentials->tail(b)]) << "arc " << a;
      }
    }
    // And every difference of potentials is consistent.
    std::vector<int64_t> any_u(potentials->num_potentials());
    for (int64_t& v : any_u) v = length(random);
    std::vector<int64_t> difference(mesh.num_arcs());
    for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
      const BundleId b = bundles.bundle_of(a);
      difference[a] = any_u[potentials->head(b)] - any_u[potentials->tail(b)];
    }
    for (int r = 0; r < consistency.num_rows(); ++r) {
      EXPECT_EQ(consistency.RowValue(r, difference), 0) << "row " << r;
    }
  }
}

TEST(BundlePotentialsTest, AHandleLeavesConsistentQuantizationsThatAreNoDifferences) {
  // A ring of eight blocks around a hole: the two sides of the hole may differ in length under
  // consistency alone, which no potentials express.
  GridTMeshSpec spec = testing::RingAroundAHole();
  const GridTMesh grid = testing::BuildGridTMeshOrDie(spec);
  EXPECT_FALSE(PotentialsOf(testing::TMeshOrDie(grid.proto())).has_value());
  // Closing the hole makes the same blocks a solid without a handle.
  spec.blocks.push_back(GridBox{{1, 1, 0}, {2, 2, 1}});
  EXPECT_TRUE(
      PotentialsOf(testing::TMeshOrDie(testing::BuildGridTMeshOrDie(spec).proto())).has_value());
}

TEST(BundlePotentialsTest, RealMeshesHaveThemOnlyWithGlobalFramesAndNoHandle) {
  // A cube; a polycube femur (global frames, no handle); a prism around a singular arc; the
  // double torus of the dual-sheet-meshing paper (global frames, two handles).
  const std::string dir = "metamesh-guided-hexalab/";
  EXPECT_TRUE(
      PotentialsOf(testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json")))
          .has_value());
  EXPECT_TRUE(
      PotentialsOf(testing::LoadTMeshOrDie(testing::RealTMeshPath(
                       dir + "2016_-_Polycube_simplification_for_coarse_layouts_of_surfaces_and_"
                             "volumes_femur_polycube_out.tmesh.json")))
          .has_value());
  EXPECT_FALSE(
      PotentialsOf(testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s02c_prism.tmesh.json")))
          .has_value());
  EXPECT_FALSE(PotentialsOf(testing::LoadTMeshOrDie(testing::RealTMeshPath(
                                dir + "2019_-_Dual_Sheet_Meshing_-_An_Interactive_Approach_to_"
                                      "Robust_Hexahedralization_double-torus.tmesh.json")))
                   .has_value());
}

}  // namespace
}  // namespace ispq
