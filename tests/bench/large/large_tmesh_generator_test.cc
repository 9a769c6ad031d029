// SPDX-License-Identifier: Apache-2.0
// The large synthetic T-meshes of the scaling benchmark: every family, at a size the unit tests
// afford, is deterministic, loads with the product's loader (also from the JSON file it writes,
// read back as `ispq stats` reads it), has its features and, except for the slabs, couples each
// axis into one subproblem; the rotated family has transitions. (The assembly families'
// statistics are tested in assembly_tmesh_generator_test.cc.)
#include "tests/bench/large/large_tmesh_generator.h"

#include <filesystem>
#include <fstream>
#include <string>

#include "core/mesh_stats.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq::bench {
namespace {

class LargeTMeshGeneratorTest : public ::testing::TestWithParam<LargeFamily> {};

TEST_P(LargeTMeshGeneratorTest, BuildsAValidConnectedPartWithFeatures) {
  const absl::StatusOr<testing::GridTMesh> grid = BuildLargeTMesh(GetParam(), 2000, 7);
  ASSERT_TRUE(grid.ok()) << grid.status();
  EXPECT_NEAR(grid->proto().arcs_size(), 2000, 2000 * 0.15);
  const TMesh mesh = testing::TMeshOrDie(grid->proto());
  const MeshStats stats = ComputeMeshStats(mesh);
  EXPECT_GT(stats.critical_arcs, 0);
  int feature_arcs = 0, feature_patches = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) feature_arcs += mesh.arc_feature(a);
  for (PatchId p = 0; p < mesh.num_patches(); ++p) feature_patches += mesh.patch_feature(p);
  EXPECT_GT(feature_arcs, 0);
  EXPECT_GT(feature_patches, 0);
  if (GetParam() == LargeFamily::kSlabs) {
    EXPECT_GT(stats.subproblems, 3);  // one per layer's vertical arcs, and more
  } else if (AssemblyDensityOf(GetParam()).has_value()) {
    EXPECT_GE(stats.subproblems, 3);  // one per axis, and a few parts cut off by voids
  } else {
    EXPECT_EQ(stats.subproblems, 3);  // one per axis: consistency never mixes axes
  }
  int rotated = 0;
  for (PatchId p = 0; p < mesh.num_patches(); ++p) rotated += !mesh.patch_rotation(p).IsIdentity();
  if (GetParam() == LargeFamily::kRotated) {
    EXPECT_GT(rotated, mesh.num_patches() / 2);
  } else {
    EXPECT_EQ(rotated, 0);
  }
  // Same seed, same mesh.
  const absl::StatusOr<testing::GridTMesh> again = BuildLargeTMesh(GetParam(), 2000, 7);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->proto().SerializeAsString(), grid->proto().SerializeAsString());

  // As a file: written as JSON, read back and validated the way `ispq stats` does, so that the
  // file the scaling benchmark hands to the product passes every format rule the loader checks.
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("ispq-large-" + std::string(LargeFamilyName(GetParam())));
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "part.tmesh.json";
  std::ofstream(file) << *testing::TMeshToJson(grid->proto());
  const absl::StatusOr<TMeshMessage> read = ReadTMeshFile(file.string());
  ASSERT_TRUE(read.ok()) << read.status();
  const absl::StatusOr<TMesh> loaded = TMeshFromProto(read->get());
  ASSERT_TRUE(loaded.ok()) << loaded.status();
  EXPECT_EQ(loaded->num_arcs(), mesh.num_arcs());
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Families, LargeTMeshGeneratorTest,
                         ::testing::Values(LargeFamily::kSingleSubproblem, LargeFamily::kSlabs,
                                           LargeFamily::kRotated, LargeFamily::kAssembly16,
                                           LargeFamily::kAssembly50, LargeFamily::kAssembly100),
                         [](const auto& info) { return std::string(LargeFamilyName(info.param)); });

}  // namespace
}  // namespace ispq::bench
