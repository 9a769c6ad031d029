// SPDX-License-Identifier: Apache-2.0
// CheckTargetsRepresentable: a scaling whose longest target is exactly kMaxTargetLength passes
// and the next larger one is refused naming the longest arc; a scaling whose continuous hex
// count passes kMaxTargetHexes is refused naming the count, even when every target fits.
#include "core/quantization_limits.h"

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

// One block 1024 long along u and `thickness` along v and w.
TMesh Slab(double thickness) {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  spec.spacing = {{{1024.0}, {thickness}, {thickness}}};
  absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(spec);
  EXPECT_TRUE(grid.ok()) << grid.status();
  return testing::TMeshOrDie(grid->proto());
}

TEST(QuantizationLimitsTest, TheLongestTargetMayReachTheLimitButNotPassIt) {
  const TMesh mesh = Slab(1e-6);  // too thin for the hex count to matter
  ArcId longest = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    if (mesh.arc_length(a) > mesh.arc_length(longest)) longest = a;
  }
  ASSERT_EQ(mesh.arc_length(longest), 1024.0);
  const double at_limit = kMaxTargetLength / 1024;  // exact: both are powers of two
  EXPECT_TRUE(CheckTargetsRepresentable(mesh, at_limit).ok());
  const double above = std::nextafter(at_limit, std::numeric_limits<double>::infinity());
  const absl::Status status = CheckTargetsRepresentable(mesh, above);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(status.message()),
              HasSubstr(absl::StrCat(" gives arc ", longest, " the target length ")));
  EXPECT_THAT(std::string(status.message()), HasSubstr("above the limit of 2.68435e+08"));
}

TEST(QuantizationLimitsTest, TooManyHexesAreRefusedEvenWhenEveryTargetFits) {
  const TMesh mesh = Slab(1.0);  // continuous volume 1024
  // s^3 * 1024 <= 1e15 for s up to about 9921.
  EXPECT_TRUE(CheckTargetsRepresentable(mesh, 9900).ok());
  const absl::Status status = CheckTargetsRepresentable(mesh, 10000);
  EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(status.message(),
            "scaling 10000 asks for about 1.024e+15 hexes, above the limit of 1e+15");
}

}  // namespace
}  // namespace ispq
