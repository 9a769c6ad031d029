// SPDX-License-Identifier: Apache-2.0
// Quantize() on tiny synthetic T-meshes whose optimal quantization is known: found by
// enumerating every consistent q near the targets in order of objective until the validator
// accepts one (tests/support/enumerated_optimum.h).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/quantization_validator.h"
#include "core/quantizer.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/enumerated_optimum.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"
#include "tests/support/worked_examples.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::ExtrudeLayout;
using ::ispq::testing::GridLayout2D;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;

GridTMesh Build(const GridTMeshSpec& spec) {
  absl::StatusOr<GridTMesh> mesh = BuildGridTMesh(spec);
  EXPECT_TRUE(mesh.ok()) << spec.name << ": " << mesh.status();
  return *std::move(mesh);
}

// Quantizes, requires a valid result, and compares with the enumerated optimum.
void ExpectOptimal(const GridTMeshSpec& spec, double scaling, int radius = 1) {
  const GridTMesh grid = Build(spec);
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  QuantizeOptions options;
  options.scaling = scaling;
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  ASSERT_TRUE(result.ok()) << spec.name << ": " << result.status();
  EXPECT_TRUE(result->valid) << spec.name;
  const absl::StatusOr<testing::EnumeratedOptimum> optimum =
      testing::EnumerateOptimum(mesh, scaling, radius);
  ASSERT_TRUE(optimum.ok()) << spec.name << ": " << optimum.status();
  EXPECT_NEAR(result->objective, optimum->objective, 1e-9) << spec.name;
}

TEST(QuantizerGridTest, SingleBlockRoundsEachAxis) {
  GridTMeshSpec spec;
  spec.name = "box";
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  spec.spacing = {std::vector<double>{2.3}, std::vector<double>{3.6}, std::vector<double>{0.7}};
  const GridTMesh grid = Build(spec);
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  QuantizeOptions options;
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  ASSERT_TRUE(result.ok()) << result.status();
  ASSERT_TRUE(result->valid);
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const auto& [from, to] = grid.arc_ends(a);
    const int axis = from[0] != to[0] ? 0 : (from[1] != to[1] ? 1 : 2);
    EXPECT_EQ(result->q[a], (std::vector<int64_t>{2, 4, 1})[axis]) << a;
  }
  EXPECT_EQ(result->hexes, 8);
  EXPECT_NEAR(result->objective, 4 * (0.09 + 0.16 + 0.09), 1e-9);
}

// Two half-width blocks on a full-width one: the T-junction makes the lower width the sum of
// the upper ones, so rounding each arc on its own is inconsistent.
TEST(QuantizerGridTest, TJunctionBalancesRoundingAcrossTheJunction) {
  GridLayout2D layout;
  layout.name = "t_junction";
  layout.blocks = {{{0, 0}, {2, 1}}, {{0, 1}, {1, 2}}, {{1, 1}, {2, 2}}};
  layout.spacing = {std::vector<double>{1.4, 1.4}, std::vector<double>{1.0, 1.0}};
  for (double scaling : {1.0, 1.3, 2.2, 3.7}) ExpectOptimal(ExtrudeLayout(layout), scaling);
}

TEST(QuantizerGridTest, LShapeWithAConcaveEdge) {
  GridLayout2D layout;
  layout.name = "l_shape";
  layout.blocks = {{{0, 0}, {1, 1}}, {{1, 0}, {2, 1}}, {{0, 1}, {1, 2}}};
  layout.spacing = {std::vector<double>{0.8, 2.6}, std::vector<double>{1.7, 0.6}};
  for (double scaling : {0.4, 1.0, 1.9}) ExpectOptimal(ExtrudeLayout(layout), scaling);
}

// Example A (core/README.md, section Cases with known answers): a feature node whose mid and low
// rows are thinner than 1/2. Plain rounding would put it on the bottom boundary; separation demands
// a sheet below it.
TEST(QuantizerGridTest, FeatureNodeNearTheBoundaryKeepsASheetBelowIt) {
  const GridTMeshSpec spec = ExtrudeLayout(testing::SeparationExampleA());
  for (double scaling : {0.8, 1.0}) ExpectOptimal(spec, scaling);
  const GridTMesh grid = Build(spec);
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  QuantizeOptions options;
  options.scaling = 0.8;
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  ASSERT_TRUE(result.ok());
  ASSERT_TRUE(result->valid);
  // F = (1, 2): the mid row below it (arc d, from I = (1, 1)) and the low row (its height is
  // that of the left boundary arc l0) must not both collapse.
  const int d = grid.ArcBetween({1, 1, 0}, {1, 2, 0});
  const int l0 = grid.ArcBetween({0, 0, 0}, {0, 1, 0});
  ASSERT_GE(d, 0);
  ASSERT_GE(l0, 0);
  EXPECT_LT(0.8 * (mesh.arc_length(d) + mesh.arc_length(l0)), 1.0);  // targets alone say 0
  EXPECT_GE(result->q[d] + result->q[l0], 1);
}

// The U-turn of T-junctions (paper Figs. 6/7) whose sheet LPs have half-integral vertices.
TEST(QuantizerGridTest, HalfIntegralSheetsAreScaledToIntegers) {
  const testing::HalfIntegerSheetExample example = testing::MakeHalfIntegerSheetExample();
  const GridTMesh grid = Build(example.spec);
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  int64_t rational = 0;
  for (double scaling : {0.6, 1.0, 1.7, 2.5, 4.0}) {
    QuantizeOptions options;
    options.scaling = scaling;
    const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
    ASSERT_TRUE(result.ok()) << result.status();
    EXPECT_TRUE(result->valid) << scaling;
    const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, result->q);
    ASSERT_TRUE(report.ok());
    EXPECT_TRUE(report->valid()) << report->Describe();
    rational += result->stats.lcd_two + result->stats.lcd_more;
  }
  EXPECT_GT(rational, 0);
}

}  // namespace
}  // namespace ispq
