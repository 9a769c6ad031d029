// SPDX-License-Identifier: Apache-2.0
// Every real T-mesh (tests/data/tmesh) loads through the JSON mapping, validates, and agrees with
// the counts its exporter wrote; opposite patch sides have equal continuous length.
#include <cmath>

#include "core/arc_bundles.h"
#include "core/block_extents.h"
#include "core/consistency_matrix.h"
#include "core/mesh_stats.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/subproblems.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

class RealTMeshTest : public ::testing::TestWithParam<std::string> {};

TEST(RealTMeshSetTest, IsPresent) {
  // The real set is required; without it the parameterized tests below would silently vanish.
  EXPECT_EQ(testing::RealTMeshFiles().size(), 62u) << "in " << testing::RealTMeshDir();
}

TEST_P(RealTMeshTest, LoadsAndMatchesExporterCounts) {
  const v1::TMesh proto = testing::LoadProtoOrDie(GetParam());
  const absl::StatusOr<TMesh> mesh = TMeshFromProto(proto);
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  const MeshStats stats = ComputeMeshStats(*mesh);
  const v1::FileStats& file = proto.stats();
  EXPECT_EQ(stats.nodes, file.nodes());
  EXPECT_EQ(stats.arcs, file.arcs());
  EXPECT_EQ(stats.patches, file.patches());
  EXPECT_EQ(stats.blocks, file.blocks());
  EXPECT_EQ(stats.critical_nodes, file.critical_nodes());
  EXPECT_EQ(stats.critical_arcs, file.critical_arcs());
  EXPECT_EQ(stats.critical_patches, file.critical_patches());
  ASSERT_EQ(file.critical_entities_by_dim_size(), 3);
  EXPECT_EQ(stats.critical_links, file.critical_entities_by_dim(1));
  EXPECT_EQ(stats.critical_regions, file.critical_entities_by_dim(2));
  EXPECT_EQ(mesh->levels().size(), 8u);
}

TEST_P(RealTMeshTest, OppositePatchSidesHaveEqualContinuousLength) {
  const TMesh mesh = testing::LoadTMeshOrDie(GetParam());
  const ConsistencyMatrix consistency(mesh);
  for (int r = 0; r < consistency.num_rows(); ++r) {
    double difference = 0, scale = 0;
    for (const LinearTerm& t : consistency.row(r)) {
      difference += t.coef * mesh.arc_length(t.var);
      scale += mesh.arc_length(t.var);
    }
    EXPECT_LE(std::abs(difference), 1e-9 * scale) << "patch " << consistency.row_info(r).patch;
  }
}

TEST_P(RealTMeshTest, BundledArcsHaveEqualTargets) {
  // Arcs forced equal by consistency must have equal continuous lengths in a consistent input.
  const TMesh mesh = testing::LoadTMeshOrDie(GetParam());
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    const double first = mesh.arc_length(bundles.arcs(b)[0]);
    for (ArcId a : bundles.arcs(b)) EXPECT_NEAR(mesh.arc_length(a), first, 1e-9 * first);
  }
}

TEST_P(RealTMeshTest, NoConstraintCrossesSubproblems) {
  const TMesh mesh = testing::LoadTMeshOrDie(GetParam());
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const Subproblems subproblems(mesh, consistency, bundles);
  auto expect_one_subproblem = [&](std::span<const LinearTerm> arc_terms) {
    const std::vector<LinearTerm> terms = bundles.ToBundleTerms(arc_terms);
    for (const LinearTerm& t : terms) {
      EXPECT_EQ(subproblems.subproblem_of(t.var), subproblems.subproblem_of(terms[0].var));
    }
  };
  for (int r = 0; r < consistency.num_rows(); ++r) expect_one_subproblem(consistency.row(r));
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<LinearTerm> row;
      for (ArcId a : ExtentRowArcs(mesh, b, axis)) row.push_back({a, 1});
      expect_one_subproblem(row);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllFiles, RealTMeshTest, ::testing::ValuesIn(testing::RealTMeshFiles()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name;
                           for (char c : testing::ShortName(info.param)) {
                             name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace ispq
