// SPDX-License-Identifier: Apache-2.0
// The bundle-level quantization and its incrementally kept objective d(q) = sum (q_a - s l_a)^2.
#include "core/isp/bundle_quantization.h"

#include <cmath>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

double ObjectiveFromScratch(const TMesh& mesh, double scaling, const std::vector<int64_t>& q) {
  double sum = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    sum += std::pow(static_cast<double>(q[a]) - scaling * mesh.arc_length(a), 2);
  }
  return sum;
}

TEST(BundleQuantizationTest, StartsAtZeroWithTheSumOfSquaredTargets) {
  const TMesh mesh =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s02c_prism.tmesh.json"));
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const BundleQuantization x(mesh, bundles, 0.3);
  const std::vector<int64_t> q = x.ArcValues();
  EXPECT_EQ(q, std::vector<int64_t>(mesh.num_arcs(), 0));
  EXPECT_NEAR(x.objective(), ObjectiveFromScratch(mesh, 0.3, q), 1e-9);
}

TEST(BundleQuantizationTest, IncrementalObjectiveMatchesRecomputation) {
  const TMesh mesh =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s02c_prism.tmesh.json"));
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  BundleQuantization x(mesh, bundles, 0.3);
  ASSERT_GE(bundles.num_bundles(), 3);
  // Arbitrary moves (consistency is not the point here).
  IntegerSheet sheet;
  sheet.bundles = {0, 2};
  sheet.deltas = {3, -1};
  const StepQuadratic f = x.Quadratic(sheet);
  const double before = x.objective();
  x.Apply(sheet, 2);
  EXPECT_NEAR(x.objective() - before, f.At(2), 1e-9);
  EXPECT_EQ(x.value(0), 6);
  EXPECT_EQ(x.value(2), -2);
  const std::vector<int64_t> q = x.ArcValues();
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) EXPECT_EQ(q[a], x.value(bundles.bundle_of(a)));
  EXPECT_NEAR(x.objective(), ObjectiveFromScratch(mesh, 0.3, q), 1e-9);
  EXPECT_NEAR(x.objective(), x.ExactObjective(), 1e-9);
  EXPECT_NEAR(
      x.MoveChange(1, 2),
      [&] {
        BundleQuantization y(mesh, bundles, 0.3);
        y.SetValues(x.values());
        IntegerSheet one;
        one.bundles = {1};
        one.deltas = {2};
        const double start = y.objective();
        y.Apply(one, 1);
        return y.objective() - start;
      }(),
      1e-9);
}

TEST(BundleQuantizationTest, MeanDeviationIsTheBundlesOwnOptimumShift) {
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  ASSERT_EQ(bundles.num_bundles(), 3);  // the four parallel edges of each axis
  const BundleQuantization x(mesh, bundles, 0.05);
  for (BundleId b = 0; b < 3; ++b) {
    double mean = 0;
    for (double t : x.targets(b)) mean += t;
    mean /= x.arc_count(b);
    EXPECT_NEAR(x.mean_deviation(b), mean, 1e-12);
    EXPECT_EQ(x.arc_count(b), 4);
  }
}

}  // namespace
}  // namespace ispq
