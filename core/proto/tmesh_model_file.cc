// SPDX-License-Identifier: Apache-2.0
#include "core/proto/tmesh_model_file.h"

#include <fcntl.h>

#include <filesystem>
#include <memory>
#include <system_error>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/proto/tmesh_from_wire.h"
#include "core/read_file.h"
#include "google/protobuf/io/zero_copy_stream_impl.h"

namespace ispq {
namespace {

absl::Status NamingFile(const std::string& path, const absl::Status& status) {
  return absl::Status(status.code(), absl::StrCat(path, ": ", status.message()));
}

// The size limit of ReadFileToString, checked before the first pass reads anything.
absl::Status CheckFileSize(const std::string& path) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) return absl::NotFoundError(absl::StrCat(path, ": cannot open file"));
  if (size > kMaxTMeshFileBytes) return FileTooLargeError(path, size, kMaxTMeshFileBytes);
  return absl::OkStatus();
}

absl::StatusOr<TMesh> DecodeBinaryFile(const std::string& path) {
  if (absl::Status size = CheckFileSize(path); !size.ok()) return size;
  // Each pass opens the file anew. One that cannot (the file went away in between) reads as an
  // empty stream, which the decoder refuses as a cut-off or different mesh.
  const TMeshBytesReader read = [&path] {
    auto stream = std::make_unique<google::protobuf::io::FileInputStream>(
        ::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    stream->SetCloseOnDelete(true);
    return std::unique_ptr<google::protobuf::io::ZeroCopyInputStream>(std::move(stream));
  };
  absl::StatusOr<TMesh> mesh = TMeshFromWire(read);
  if (!mesh.ok()) return NamingFile(path, mesh.status());
  return mesh;
}

}  // namespace

absl::StatusOr<TMesh> ReadTMeshModelFile(const std::string& path) {
  if (IsBinaryTMeshPath(path)) return DecodeBinaryFile(path);
  absl::StatusOr<TMeshMessage> message = ReadTMeshFile(path);
  if (!message.ok()) return message.status();  // its message names the file already
  absl::StatusOr<TMesh> mesh = TMeshFromProto(message->get());
  if (!mesh.ok()) return NamingFile(path, mesh.status());
  return mesh;
}

}  // namespace ispq
