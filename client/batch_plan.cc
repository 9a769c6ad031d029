// SPDX-License-Identifier: Apache-2.0
#include "client/batch_plan.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <set>
#include <system_error>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace ispq::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMeshExtensions[] = {".tmesh.json", ".tmesh.pb", ".tmesh.binpb"};

// The file name without its T-mesh extension, or "" if it has none.
std::string MeshStem(const std::string& path) {
  for (const char* extension : kMeshExtensions) {
    if (absl::EndsWith(path, extension) && path.size() > std::string(extension).size()) {
      return path.substr(0, path.size() - std::string(extension).size());
    }
  }
  return "";
}

struct FoundMesh {
  std::string path;
  std::string relative_stem;  // "hex-me/s07c_notch"
};

absl::Status FindMeshes(const std::string& input, std::vector<FoundMesh>& found) {
  std::error_code error;
  if (fs::is_directory(input, error)) {
    const size_t before = found.size();
    for (fs::recursive_directory_iterator it(input, error), end; !error && it != end;
         it.increment(error)) {
      if (!it->is_regular_file(error)) continue;
      const std::string relative = fs::relative(it->path(), input, error).generic_string();
      const std::string stem = MeshStem(relative);
      if (!stem.empty()) found.push_back({it->path().string(), stem});
    }
    if (error) return absl::InvalidArgumentError(absl::StrCat(input, ": ", error.message()));
    if (found.size() == before) {
      return absl::InvalidArgumentError(absl::StrCat(
          input, ": no T-mesh files in it (.tmesh.json, ", ".tmesh.pb, .tmesh.binpb)"));
    }
    return absl::OkStatus();
  }
  const std::string stem = MeshStem(fs::path(input).filename().string());
  if (stem.empty() || !fs::is_regular_file(input, error)) {
    return absl::InvalidArgumentError(absl::StrCat(
        input, ": not a T-mesh file (.tmesh.json, .tmesh.pb, .tmesh.binpb) or a ", "directory"));
  }
  found.push_back({input, stem});
  return absl::OkStatus();
}

// FNV-1a: stable across builds and machines, unlike std::hash and absl::Hash.
uint64_t Fnv1a(std::string_view bytes, uint64_t hash = 14695981039346656037ull) {
  for (const unsigned char byte : bytes) {
    hash ^= byte;
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace

std::string ScalingLabel(const v1::Scaling& scaling) {
  switch (scaling.kind_case()) {
    case v1::Scaling::kLevelPercent:
      return absl::StrCat("L", scaling.level_percent());
    case v1::Scaling::kFactor:
      return absl::StrFormat("s%g", scaling.factor());
    case v1::Scaling::kTargetHexes:
      return absl::StrCat("h", scaling.target_hexes());
    case v1::Scaling::KIND_NOT_SET:
      break;
  }
  return "default";
}

absl::StatusOr<std::vector<BatchJob>> PlanBatch(
    const std::vector<std::string>& inputs, const std::vector<v1::QuantizationOptions>& variants,
    const std::string& out_dir) {
  std::vector<FoundMesh> meshes;
  for (const std::string& input : inputs) {
    if (absl::Status found = FindMeshes(input, meshes); !found.ok()) return found;
  }
  std::stable_sort(meshes.begin(), meshes.end(), [](const FoundMesh& a, const FoundMesh& b) {
    return a.relative_stem < b.relative_stem;
  });
  std::vector<BatchJob> jobs;
  std::set<std::string> result_paths;
  for (const FoundMesh& mesh : meshes) {
    for (const v1::QuantizationOptions& options : variants) {
      const std::string label = ScalingLabel(options.scaling());
      BatchJob job{
          mesh.path, absl::StrCat(mesh.relative_stem, " ", label), options,
          (fs::path(out_dir) / absl::StrCat(mesh.relative_stem, ".", label, ".result.json"))
              .string()};
      if (!result_paths.insert(job.result_path).second) {
        return absl::InvalidArgumentError(
            absl::StrCat(mesh.path, ": another input has the same name (", mesh.relative_stem,
                         "): both would write ", job.result_path));
      }
      jobs.push_back(std::move(job));
    }
  }
  return jobs;
}

std::string BatchRequestId(const v1::QuantizeRequest& request, const std::string& result_path) {
  v1::QuantizeRequest without_id = request;
  without_id.clear_request_id();
  std::string bytes;
  without_id.SerializeToString(&bytes);
  return absl::StrFormat("batch-%016x-%016x", Fnv1a(bytes), Fnv1a(result_path));
}

}  // namespace ispq::cli
