// SPDX-License-Identifier: Apache-2.0
// Bundles of arcs that every consistent q keeps equal (paper section 4.4).
#include "core/arc_bundles.h"

#include <cstdint>
#include <vector>

#include "core/consistency_matrix.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

TEST(ArcBundlesTest, TheCubesParallelArcsFormOneBundlePerAxis) {
  const TMesh cube = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const ConsistencyMatrix consistency(cube);
  const ArcBundles bundles(cube, consistency);
  EXPECT_EQ(bundles.num_bundles(), 3);  // the 4 parallel edges of each axis
  for (BundleId b = 0; b < 3; ++b) {
    EXPECT_EQ(bundles.arcs(b).size(), 4u);
    for (ArcId a : bundles.arcs(b)) EXPECT_EQ(bundles.bundle_of_arc()[a], b);
  }
  // Arc values are their bundle's.
  const std::vector<int64_t> q = bundles.ArcValues(std::vector<int64_t>{2, 3, 4});
  for (ArcId a = 0; a < cube.num_arcs(); ++a) EXPECT_EQ(q[a], 2 + bundles.bundle_of_arc()[a]);
}

TEST(ArcBundlesTest, BundlingMergesTerms) {
  const TMesh prism =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s02c_prism.tmesh.json"));
  const ConsistencyMatrix consistency(prism);
  const ArcBundles bundles(prism, consistency);
  // A row whose two sides are one arc each vanishes once both arcs share a bundle.
  for (int r = 0; r < consistency.num_rows(); ++r) {
    if (consistency.row(r).size() == 2) {
      EXPECT_TRUE(bundles.ToBundleTerms(consistency.row(r)).empty());
    }
  }
  EXPECT_LT(bundles.num_bundles(), prism.num_arcs());
}

// A row over bundles written back over arcs names each bundle by its smallest arc, and bundling
// that gives the row again.
TEST(ArcBundlesTest, BundleTermsWrittenOverArcsNameEachBundleByItsSmallestArc) {
  const TMesh cube = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const ConsistencyMatrix consistency(cube);
  const ArcBundles bundles(cube, consistency);
  const std::vector<LinearTerm> row = {{0, 1}, {1, -1}, {2, 2}};
  const std::vector<LinearTerm> over_arcs = bundles.ToArcTerms(row);
  ASSERT_EQ(over_arcs.size(), row.size());
  for (size_t i = 0; i < row.size(); ++i) {
    EXPECT_EQ(over_arcs[i].var, bundles.arcs(row[i].var)[0]);
    EXPECT_EQ(over_arcs[i].coef, row[i].coef);
  }
  EXPECT_EQ(bundles.ToBundleTerms(over_arcs), row);
}

}  // namespace
}  // namespace ispq
