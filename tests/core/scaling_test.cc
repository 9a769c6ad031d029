// SPDX-License-Identifier: Apache-2.0
// Resolving the caller's choice of scaling factor against a mesh: a factor is taken as it is, a
// level is the format's factor for that percent, a hex count inverts the continuous block volume;
// bad choices are INVALID_ARGUMENT with a message that names the value.
#include "core/scaling.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/block_extents.h"
#include "core/resolution_levels.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

const TMesh& Tetrahedron() {
  static const TMesh* const kMesh = new TMesh(
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s04u_tetrahedron.tmesh.json")));
  return *kMesh;
}

void ExpectRejected(const ScalingChoice& choice, const std::string& message) {
  const absl::StatusOr<double> s = ResolveScaling(choice, Tetrahedron());
  ASSERT_FALSE(s.ok()) << message;
  EXPECT_EQ(s.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.status().message()), HasSubstr(message));
}

TEST(ScalingTest, FactorIsTakenAsItIs) {
  EXPECT_EQ(*ResolveScaling(ScalingChoice::Factor(2.5), Tetrahedron()), 2.5);
}

TEST(ScalingTest, LevelIsTheFormatsFactor) {
  for (int percent : kLevelPercents) {
    EXPECT_EQ(*ResolveScaling(ScalingChoice::LevelPercent(percent), Tetrahedron()),
              *ScalingForPercent(Tetrahedron().arc_lengths(), percent))
        << percent;
  }
}

TEST(ScalingTest, TargetHexesInvertsTheContinuousVolume) {
  const double s = *ResolveScaling(ScalingChoice::TargetHexes(1000), Tetrahedron());
  EXPECT_NEAR(s * s * s * ContinuousHexVolume(Tetrahedron()), 1000.0, 1e-9);
}

TEST(ScalingTest, BadChoicesAreRejectedNamingTheValue) {
  ExpectRejected(ScalingChoice(), "no scaling given");
  ExpectRejected(ScalingChoice::Factor(0), "scaling factor 0 is not a positive finite number");
  ExpectRejected(ScalingChoice::Factor(-1), "scaling factor -1 is not");
  ExpectRejected(ScalingChoice::Factor(std::nan("")), "scaling factor nan is not");
  ExpectRejected(ScalingChoice::Factor(std::numeric_limits<double>::infinity()),
                 "scaling factor inf is not");
  ExpectRejected(ScalingChoice::LevelPercent(3), "level 3 is not one of 0, 1, 5, 10");
  ExpectRejected(ScalingChoice::TargetHexes(0), "target hex count 0 is not positive");
  ExpectRejected(ScalingChoice::TargetHexes(-8), "target hex count -8 is not positive");
}

}  // namespace
}  // namespace ispq
