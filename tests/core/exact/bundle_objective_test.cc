// SPDX-License-Identifier: Apache-2.0
// The objective split over bundles and its piecewise-linear form on the integers
// (core/exact/bundle_objective.h): values, best integers, windows and secants on a mesh whose
// targets are known.
#include "core/exact/bundle_objective.h"

#include <cmath>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

// One block with edge lengths 2.3, 3.6 and 0.7: three bundles of four arcs each.
TMesh Box() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  spec.spacing = {std::vector<double>{2.3}, std::vector<double>{3.6}, std::vector<double>{0.7}};
  return testing::TMeshOrDie(testing::BuildGridTMesh(spec)->proto());
}

double Target(const TMesh& mesh, const ArcBundles& bundles, BundleId b) {
  return mesh.arc_length(bundles.arcs(b)[0]);
}

TEST(BundleObjectivesTest, ValuesBestIntegersAndMinimum) {
  const TMesh mesh = Box();
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  ASSERT_EQ(bundles.num_bundles(), 3);
  const BundleObjectives objectives(mesh, bundles, 1.0);
  double minimum = 0;
  for (BundleId b = 0; b < 3; ++b) {
    const double t = Target(mesh, bundles, b);
    EXPECT_EQ(objectives.BestInteger(b), std::llround(t));
    EXPECT_NEAR(objectives.Value(b, 5), 4 * (5 - t) * (5 - t), 1e-12);
    minimum += objectives.Value(b, std::llround(t));
  }
  EXPECT_NEAR(objectives.MinimumSum(), minimum, 1e-12);
  EXPECT_NEAR(minimum, 4 * (0.09 + 0.16 + 0.09), 1e-12);
  EXPECT_NEAR(objectives.Objective(std::vector<int64_t>{2, 4, 1}), minimum, 1e-12);
}

// The window holds exactly the integers within the slack of the best value.
TEST(BundleObjectivesTest, WindowsHoldExactlyTheIntegersWithinTheSlack) {
  const TMesh mesh = Box();
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const BundleObjectives objectives(mesh, bundles, 3.0);
  for (double slack : {0.0, 0.5, 4.0, 37.0, 1000.0}) {
    for (BundleId b = 0; b < 3; ++b) {
      const IntegerWindow window = objectives.Window(b, slack);
      const double limit = objectives.Value(b, objectives.BestInteger(b)) + slack;
      EXPECT_LE(window.lo, objectives.BestInteger(b));
      EXPECT_GE(window.hi, objectives.BestInteger(b));
      for (int64_t x = window.lo; x <= window.hi; ++x) EXPECT_LE(objectives.Value(b, x), limit);
      EXPECT_GT(objectives.Value(b, window.lo - 1), limit) << slack << " " << b;
      EXPECT_GT(objectives.Value(b, window.hi + 1), limit) << slack << " " << b;
    }
  }
}

// Every secant between consecutive integers lies below the objective at every integer and
// touches it at its two ends: the maximum of the secants is the objective on the integers.
TEST(BundleObjectivesTest, SecantsUnderestimateAtIntegersAndAreExactAtTheirEnds) {
  const TMesh mesh = Box();
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const BundleObjectives objectives(mesh, bundles, 1.7);
  for (BundleId b = 0; b < 3; ++b) {
    for (int64_t k = -3; k <= 9; ++k) {
      const Secant s = objectives.SecantAt(b, k);
      EXPECT_NEAR(s.value, objectives.Value(b, k), 1e-12);
      EXPECT_NEAR(s.value + s.slope, objectives.Value(b, k + 1), 1e-9);
      for (int64_t x = -5; x <= 12; ++x) {
        const double line = s.value + s.slope * static_cast<double>(x - k);
        EXPECT_LE(line, objectives.Value(b, x) + 1e-9) << b << " " << k << " " << x;
      }
    }
  }
}

}  // namespace
}  // namespace ispq
