// SPDX-License-Identifier: Apache-2.0
// Files the CLI's parts read in their tests: a folder of the test's own, a small valid T-mesh
// file (two unit blocks, the grid builder's), a file of it broken, and result files.
#ifndef ISPQ_TESTS_CLIENT_CLIENT_TEST_FILES_H_
#define ISPQ_TESTS_CLIENT_CLIENT_TEST_FILES_H_

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "ispq/v1/quantization.pb.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq::testing {

// A fresh folder named after the running test and this process, removed on destruction.
class TestFolder {
 public:
  TestFolder();
  ~TestFolder();
  TestFolder(const TestFolder&) = delete;
  TestFolder& operator=(const TestFolder&) = delete;

  std::string Path(const std::string& name) const { return (dir_ / name).string(); }
  // Writes `contents` to the file `name` of the folder and returns its path.
  std::string Write(const std::string& name, const std::string& contents) const;

 private:
  std::filesystem::path dir_;
};

// Two unit blocks side by side along u: 20 arcs of length 1.
const v1::TMesh& TwoBlockMesh();

// The mesh's own arc lengths as q: the grid itself, a valid quantization (checked by the
// validator in the tests that use it).
std::vector<int64_t> GridQ();

// A result message for TwoBlockMesh with q = GridQ().
v1::QuantizationResult GridResult();

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_CLIENT_CLIENT_TEST_FILES_H_
