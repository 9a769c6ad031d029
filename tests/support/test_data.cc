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

TMeshMessage ReadTMeshFileOrDie(const std::string& path) {
  absl::StatusOr<TMeshMessage> proto = ReadTMeshFile(path);
  if (!proto.ok()) {
    std::cerr << "cannot read test input " << path << ": " << proto.status() << "\n";
    std::abort();
  }
  return *std::move(proto);
}

}  // namespace

v1::TMesh LoadProtoOrDie(const std::string& path) { return ReadTMeshFileOrDie(path).get(); }

TMesh TMeshOrDie(const v1::TMesh& proto) {
  absl::StatusOr<TMesh> mesh = TMeshFromProto(proto);
  if (!mesh.ok()) {
    std::cerr << "invalid test mesh " << proto.name() << ": " << mesh.status() << "\n";
    std::abort();
  }
  return *std::move(mesh);
}

// As `ispq quantize --local` loads it (core/proto/tmesh_model_file.h): the scaling benchmark
// loads meshes of 10^6 arcs this way.
TMesh LoadTMeshOrDie(const std::string& path) {
  absl::StatusOr<TMesh> mesh = ReadTMeshModelFile(path);
  if (!mesh.ok()) {
    std::cerr << "cannot load test mesh " << path << ": " << mesh.status() << "\n";
    std::abort();
  }
  return *std::move(mesh);
}

}  // namespace ispq::testing
