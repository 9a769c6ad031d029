#include "core/tmesh_file.h"

#include <fstream>
#include <sstream>

#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "google/protobuf/util/json_util.h"

namespace ispq {

absl::StatusOr<v1::TMesh> ParseTMeshJson(std::string_view json) {
  v1::TMesh mesh;
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;  // a misspelled key is an error, not a silent default
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(json.data(), json.size()), &mesh, options);
  if (!status.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("not a T-mesh JSON document: ", std::string(status.message())));
  }
  return mesh;
}

absl::StatusOr<v1::TMesh> ParseTMeshBinary(std::string_view bytes) {
  v1::TMesh mesh;
  if (!mesh.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) {
    return absl::InvalidArgumentError("not a binary ispq.v1.TMesh message");
  }
  return mesh;
}

absl::StatusOr<std::string> ReadFileToString(const std::string& path, size_t max_bytes) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return absl::NotFoundError(absl::StrCat(path, ": cannot open file"));
  const std::streamoff size = in.tellg();
  if (size < 0) return absl::InvalidArgumentError(absl::StrCat(path, ": cannot read file"));
  if (static_cast<size_t>(size) > max_bytes) {
    return absl::InvalidArgumentError(
        absl::StrCat(path, ": file has ", size, " bytes, more than the limit of ", max_bytes));
  }
  std::string contents(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(contents.data(), size)) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": cannot read file"));
  }
  return contents;
}

absl::StatusOr<v1::TMesh> ReadTMeshFile(const std::string& path) {
  absl::StatusOr<std::string> contents = ReadFileToString(path, kMaxTMeshFileBytes);
  if (!contents.ok()) return contents.status();
  const bool binary = absl::EndsWith(path, ".pb") || absl::EndsWith(path, ".binpb");
  absl::StatusOr<v1::TMesh> mesh = binary ? ParseTMeshBinary(*contents) : ParseTMeshJson(*contents);
  if (!mesh.ok()) {
    return absl::Status(mesh.status().code(), absl::StrCat(path, ": ", mesh.status().message()));
  }
  return mesh;
}

}  // namespace ispq
