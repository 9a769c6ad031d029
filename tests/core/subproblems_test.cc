// SPDX-License-Identifier: Apache-2.0
#include "core/subproblems.h"

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

TEST(SubproblemsTest, TheCubesAxesAreIndependent) {
  const TMesh cube = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const ConsistencyMatrix consistency(cube);
  const ArcBundles bundles(cube, consistency);
  const Subproblems subproblems(cube, consistency, bundles);
  EXPECT_EQ(subproblems.num_subproblems(), 3);
}

}  // namespace
}  // namespace ispq
