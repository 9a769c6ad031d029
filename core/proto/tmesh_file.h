// Reading T-mesh messages from files and strings: `*.tmesh.json` through protobuf's JSON
// mapping (the format of shared/tmesh-format.md) or binary protobuf (`*.tmesh.pb`).
//
// This only parses; TMeshFromProto validates. Errors name the file and what failed to parse.
#ifndef ISPQ_CORE_PROTO_TMESH_FILE_H_
#define ISPQ_CORE_PROTO_TMESH_FILE_H_

#include <string>
#include <string_view>

#include "absl/status/statusor.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq {

// Files larger than this are refused before they are read (the largest shared file is 0.3 MiB).
inline constexpr size_t kMaxTMeshFileBytes = size_t{256} << 20;

absl::StatusOr<v1::TMesh> ParseTMeshJson(std::string_view json);
absl::StatusOr<v1::TMesh> ParseTMeshBinary(std::string_view bytes);

// Binary if the name ends in ".pb" or ".binpb", JSON otherwise.
absl::StatusOr<v1::TMesh> ReadTMeshFile(const std::string& path);

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_TMESH_FILE_H_
