// SPDX-License-Identifier: Apache-2.0
#include "core/proto/tmesh_file.h"

#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "core/read_file.h"
#include "core/status_macros.h"
#include "google/protobuf/util/json_util.h"

namespace ispq {
namespace {

absl::Status ParseJsonInto(std::string_view json, v1::TMesh* mesh) {
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;  // a misspelled key is an error, not a silent default
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(json.data(), json.size()), mesh, options);
  if (!status.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("not a T-mesh JSON document: ", std::string(status.message())));
  }
  return absl::OkStatus();
}

absl::Status ParseBinaryInto(std::string_view bytes, v1::TMesh* mesh) {
  if (!mesh->ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) {
    // Worded as core/proto/tmesh_from_wire.h words it, which reads such files for a local solve.
    return absl::InvalidArgumentError(
        "the bytes are not a binary T-mesh (ispq.v1.TMesh): it does not parse");
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<v1::TMesh> ParseTMeshJson(std::string_view json) {
  v1::TMesh mesh;
  ISPQ_RETURN_IF_ERROR(ParseJsonInto(json, &mesh));
  return mesh;
}

absl::StatusOr<v1::TMesh> ParseTMeshBinary(std::string_view bytes) {
  v1::TMesh mesh;
  ISPQ_RETURN_IF_ERROR(ParseBinaryInto(bytes, &mesh));
  return mesh;
}

TMeshMessage::TMeshMessage()
    : arena_(std::make_unique<google::protobuf::Arena>()), message_(CreateOnArena<v1::TMesh>()) {}

bool IsBinaryTMeshPath(const std::string& path) {
  return absl::EndsWith(path, ".pb") || absl::EndsWith(path, ".binpb");
}

absl::StatusOr<TMeshMessage> ReadTMeshFile(const std::string& path) {
  ISPQ_ASSIGN_OR_RETURN(const std::string contents, ReadFileToString(path, kMaxTMeshFileBytes));
  const bool binary = IsBinaryTMeshPath(path);
  TMeshMessage mesh;
  const absl::Status parsed = binary ? ParseBinaryInto(contents, mesh.mutable_message())
                                     : ParseJsonInto(contents, mesh.mutable_message());
  if (!parsed.ok()) return absl::Status(parsed.code(), absl::StrCat(path, ": ", parsed.message()));
  return mesh;
}

}  // namespace ispq
