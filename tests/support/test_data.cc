// SPDX-License-Identifier: Apache-2.0
#include "tests/support/test_data.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/proto/tmesh_model_file.h"

namespace ispq::testing {

std::string RealTMeshDir() { return ISPQ_REAL_TMESH_DIR; }

std::vector<std::string> RealTMeshFiles() {
  std::vector<std::string> files;
  std::error_code error;
  for (auto it = std::filesystem::recursive_directory_iterator(RealTMeshDir(), error);
       !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error)) {
    const std::string path = it->path().string();
    if (it->is_regular_file() && path.ends_with(".tmesh.json")) files.push_back(path);
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string RealTMeshPath(const std::string& dataset_and_file) {
  return RealTMeshDir() + "/" + dataset_and_file;
}

std::string ReferenceResultsDir() { return ISPQ_REFERENCE_DIR; }

std::string ShortName(const std::string& path) {
  const std::filesystem::path p(path);
  std::string model = p.filename().string();
  model = model.substr(0, model.size() - std::string(".tmesh.json").size());
  return p.parent_path().filename().string() + "/" + model;
}

namespace {

// The value, or the test binary aborts with `what`, `name` and the error (test inputs are expected
// to be valid).
template <typename T>
T OrDie(absl::StatusOr<T> value, const char* what, const std::string& name) {
  if (!value.ok()) {
    std::cerr << what << " " << name << ": " << value.status() << "\n";
    std::abort();
  }
  return *std::move(value);
}

}  // namespace

v1::TMesh LoadProtoOrDie(const std::string& path) {
  return OrDie(ReadTMeshFile(path), "cannot read test input", path).get();
}

TMesh TMeshOrDie(const v1::TMesh& proto) {
  return OrDie(TMeshFromProto(proto), "invalid test mesh", proto.name());
}

// As `ispq quantize --local` loads it (core/proto/tmesh_model_file.h): the scaling benchmark
// loads meshes of 10^6 arcs this way.
TMesh LoadTMeshOrDie(const std::string& path) {
  return OrDie(ReadTMeshModelFile(path), "cannot load test mesh", path);
}

}  // namespace ispq::testing
