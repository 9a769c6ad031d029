// SPDX-License-Identifier: Apache-2.0
#include "tests/client/client_test_files.h"

#include <unistd.h>

#include <cmath>
#include <fstream>

#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"

namespace ispq::testing {

TestFolder::TestFolder() {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  dir_ =
      std::filesystem::temp_directory_path() / ("ispq-client-" + std::to_string(::getpid()) + "-" +
                                                test->test_suite_name() + "-" + test->name());
  std::filesystem::remove_all(dir_);
  std::filesystem::create_directories(dir_);
}

TestFolder::~TestFolder() { std::filesystem::remove_all(dir_); }

std::string TestFolder::Write(const std::string& name, const std::string& contents) const {
  const std::string path = Path(name);
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

const v1::TMesh& TwoBlockMesh() {
  static const v1::TMesh* const kMesh = [] {
    GridTMeshSpec spec;
    spec.name = "two-blocks";
    spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
    absl::StatusOr<GridTMesh> grid = BuildGridTMesh(spec);
    EXPECT_TRUE(grid.ok()) << grid.status();
    return new v1::TMesh(grid->proto());
  }();
  return *kMesh;
}

std::vector<int64_t> GridQ() {
  std::vector<int64_t> q;
  for (const v1::Arc& arc : TwoBlockMesh().arcs()) q.push_back(std::llround(arc.length()));
  return q;
}

v1::QuantizationResult GridResult() {
  v1::QuantizationResult result;
  for (int64_t value : GridQ()) result.add_q(static_cast<int32_t>(value));
  result.set_valid(true);
  result.set_scaling(1.0);
  result.set_hexes(2);
  result.set_termination(v1::CONVERGED);
  result.set_mesh_name(TwoBlockMesh().name());
  return result;
}

}  // namespace ispq::testing
