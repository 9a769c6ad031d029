// SPDX-License-Identifier: Apache-2.0
// Node potentials: on parts with global frames and no handle, the consistent q are exactly the
// potential differences; with handles they are fewer; frames turned by a singular arc give none.
#include "core/bundle_potentials.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "core/disjoint_sets.h"
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

// The rank of the consistency rows over bundles, by elimination in doubles (small meshes; the
// coefficients are small integers).
int RankOverBundles(const ConsistencyMatrix& consistency, const ArcBundles& bundles) {
  const int n = bundles.num_bundles();
  std::vector<std::vector<double>> rows;
  for (int r = 0; r < consistency.num_rows(); ++r) {
    std::vector<double> row(n, 0.0);
    for (const LinearTerm& t : consistency.row(r)) row[bundles.bundle_of(t.var)] += t.coef;
    rows.push_back(std::move(row));
  }
  int rank = 0;
  for (int col = 0; col < n && rank < static_cast<int>(rows.size()); ++col) {
    int pivot = rank;
    for (int r = rank; r < static_cast<int>(rows.size()); ++r) {
      if (std::abs(rows[r][col]) > std::abs(rows[pivot][col])) pivot = r;
    }
    if (std::abs(rows[pivot][col]) < 1e-9) continue;
    std::swap(rows[pivot], rows[rank]);
    for (int r = rank + 1; r < static_cast<int>(rows.size()); ++r) {
      const double f = rows[r][col] / rows[rank][col];
      if (f == 0) continue;
      for (int c = col; c < n; ++c) rows[r][c] -= f * rows[rank][c];
    }
    ++rank;
  }
  return rank;
}

// How many dimensions of consistent q are no potential differences: the consistent q have
// bundles less the rank of the rows; the differences potentials less the components they form.
// Also checks that every difference is consistent.
int NonDifferenceDimensions(const TMesh& mesh) {
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const std::optional<BundlePotentials> potentials =
      BundlePotentials::Compute(mesh, consistency, bundles);
  EXPECT_TRUE(potentials.has_value());
  if (!potentials.has_value()) return -1;
  std::mt19937 random(11);
  std::uniform_int_distribution<int64_t> value(-4, 4);
  std::vector<int64_t> u(potentials->num_potentials()), q(mesh.num_arcs());
  for (int64_t& v : u) v = value(random);
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const BundleId b = bundles.bundle_of(a);
    q[a] = u[potentials->head(b)] - u[potentials->tail(b)];
  }
  for (int r = 0; r < consistency.num_rows(); ++r) EXPECT_EQ(consistency.RowValue(r, q), 0);
  DisjointSets components(potentials->num_potentials());
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    components.Join(potentials->tail(b), potentials->head(b));
  }
  int num_components = 0;
  for (int32_t v = 0; v < potentials->num_potentials(); ++v) {
    num_components += components.Find(v) == v;
  }
  return bundles.num_bundles() - RankOverBundles(consistency, bundles) -
         (potentials->num_potentials() - num_components);
}

TEST(BundlePotentialsTest, AHandleLeavesConsistentQuantizationsThatAreNoDifferences) {
  // A ring of eight blocks around a hole: the two sides of the hole may differ in length under
  // consistency alone, along either axis across it, which no potentials express.
  GridTMeshSpec spec = testing::RingAroundAHole();
  const TMesh ring = testing::TMeshOrDie(testing::BuildGridTMeshOrDie(spec).proto());
  ASSERT_TRUE(PotentialsOf(ring).has_value());
  EXPECT_TRUE(PotentialsOf(ring)->has_handles());
  EXPECT_EQ(NonDifferenceDimensions(ring), 2);
  // Closing the hole makes the same blocks a solid without a handle.
  spec.blocks.push_back(GridBox{{1, 1, 0}, {2, 2, 1}});
  const TMesh solid = testing::TMeshOrDie(testing::BuildGridTMeshOrDie(spec).proto());
  ASSERT_TRUE(PotentialsOf(solid).has_value());
  EXPECT_FALSE(PotentialsOf(solid)->has_handles());
  EXPECT_EQ(NonDifferenceDimensions(solid), 0);
}

TEST(BundlePotentialsTest, RealMeshesHaveThemOnlyWithGlobalFrames) {
  // A cube; a polycube femur (global frames, no handle); a prism around a singular arc; the
  // double torus of the dual-sheet-meshing paper (global frames, two handles).
  const std::string dir = "metamesh-guided-hexalab/";
  const TMesh cube = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  ASSERT_TRUE(PotentialsOf(cube).has_value());
  EXPECT_FALSE(PotentialsOf(cube)->has_handles());
  const TMesh femur =
      testing::LoadTMeshOrDie(testing::RealTMeshPath(
          dir + "2016_-_Polycube_simplification_for_coarse_layouts_of_surfaces_and_"
                "volumes_femur_polycube_out.tmesh.json"));
  ASSERT_TRUE(PotentialsOf(femur).has_value());
  EXPECT_FALSE(PotentialsOf(femur)->has_handles());
  EXPECT_EQ(NonDifferenceDimensions(femur), 0);
  EXPECT_FALSE(
      PotentialsOf(testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s02c_prism.tmesh.json")))
          .has_value());
  const TMesh torus = testing::LoadTMeshOrDie(
      testing::RealTMeshPath(dir + "2019_-_Dual_Sheet_Meshing_-_An_Interactive_Approach_to_"
                                   "Robust_Hexahedralization_double-torus.tmesh.json"));
  ASSERT_TRUE(PotentialsOf(torus).has_value());
  EXPECT_TRUE(PotentialsOf(torus)->has_handles());
  EXPECT_GT(NonDifferenceDimensions(torus), 0);
}

}  // namespace
}  // namespace ispq
