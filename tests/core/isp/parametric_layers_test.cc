// SPDX-License-Identifier: Apache-2.0
// The layered quantization (core/isp/parametric_layers.h): on the real T-meshes and on
// synthetic parts of every family, the layers close and their q is >= 1 on every arc and valid
// by the validator at every level; where the parametrization spirals, no q is returned.
#include "core/isp/parametric_layers.h"

#include <string>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/quantization_validator.h"
#include "gtest/gtest.h"
#include "tests/bench/large/large_tmesh_generator.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::ShortName;

// Expects a layered q on `mesh` at every level; returns false if the layers did not close.
bool ExpectValidLayeredQuantization(const TMesh& mesh, const std::string& name) {
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  for (const Level& level : mesh.levels()) {
    const BundleQuantization quantization(mesh, bundles, level.scaling);
    const std::optional<std::vector<int64_t>> values =
        QuantizeByParametricLayers(mesh, bundles, quantization);
    if (!values.has_value()) return false;
    const std::vector<int64_t> q = bundles.ArcValues(*values);
    for (ArcId a = 0; a < mesh.num_arcs(); ++a) EXPECT_GE(q[a], 1) << name << " arc " << a;
    const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, q);
    EXPECT_TRUE(report.ok() && report->valid())
        << name << " level " << level.percent << ":\n"
        << (report.ok() ? report->Describe() : report.status().ToString());
  }
  return true;
}

// The one real mesh whose layers do not close: a tubular shape whose seam carries a translation,
// so that an iso-surface comes back shifted after a turn around the tube.
constexpr char kSpiralling[] =
    "metamesh-guided-hexalab/"
    "2017_-_Explicit_Cylindrical_Maps_for_General_Tubular_Shapes_femur_shell1";

TEST(ParametricLayersTest, ValidOnEveryRealMeshWhoseLayersClose) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  std::vector<std::string> open;
  for (const std::string& file : files) {
    const TMesh mesh = LoadTMeshOrDie(file);
    if (!ExpectValidLayeredQuantization(mesh, ShortName(file))) open.push_back(ShortName(file));
  }
  EXPECT_EQ(open, std::vector<std::string>{kSpiralling});
}

class ParametricLayersFamilyTest : public ::testing::TestWithParam<bench::LargeFamily> {};

TEST_P(ParametricLayersFamilyTest, ValidOnSyntheticParts) {
  const absl::StatusOr<testing::GridTMesh> grid = bench::BuildLargeTMesh(GetParam(), 3000, 11);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = testing::TMeshOrDie(grid->proto());
  EXPECT_TRUE(ExpectValidLayeredQuantization(mesh, bench::LargeFamilyName(GetParam())));
}

INSTANTIATE_TEST_SUITE_P(Families, ParametricLayersFamilyTest,
                         ::testing::Values(bench::LargeFamily::kSingleSubproblem,
                                           bench::LargeFamily::kSlabs,
                                           bench::LargeFamily::kRotated),
                         [](const auto& info) { return bench::LargeFamilyName(info.param); });

}  // namespace
}  // namespace ispq
