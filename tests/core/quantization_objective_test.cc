// SPDX-License-Identifier: Apache-2.0
#include "core/quantization_objective.h"

#include <cmath>
#include <cstdint>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

// The sum over arcs of (q_a - s l_a)^2, by its definition, on a real mesh.
TEST(QuantizationObjectiveTest, IsTheSumOfSquaredDeviationsFromTheScaledTargets) {
  const TMesh mesh =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  const double scaling = 2.5;
  std::vector<int64_t> q(mesh.num_arcs());
  double expected = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    q[a] = a % 4;
    const double deviation = static_cast<double>(q[a]) - scaling * mesh.arc_length(a);
    expected += deviation * deviation;
  }
  EXPECT_NEAR(QuantizationObjective(mesh, q, scaling), expected, 1e-9 * expected);

  // q equal to the targets rounded can only be closer than any q shifted by one everywhere.
  std::vector<int64_t> rounded(mesh.num_arcs()), shifted(mesh.num_arcs());
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    rounded[a] = std::llround(scaling * mesh.arc_length(a));
    shifted[a] = rounded[a] + 1;
  }
  EXPECT_LT(QuantizationObjective(mesh, rounded, scaling),
            QuantizationObjective(mesh, shifted, scaling));
  EXPECT_LE(QuantizationObjective(mesh, rounded, scaling), 0.25 * mesh.num_arcs());
}

}  // namespace
}  // namespace ispq
