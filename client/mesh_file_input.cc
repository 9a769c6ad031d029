// SPDX-License-Identifier: Apache-2.0
#include "client/mesh_file_input.h"

#include <utility>

#include "absl/strings/str_cat.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/proto/tmesh_model_file.h"

namespace ispq::cli {

absl::StatusOr<MeshFile> LoadMeshFile(const std::string& path) {
  absl::StatusOr<TMeshMessage> proto = ReadTMeshFile(path);
  if (!proto.ok()) return proto.status();  // its message names the file already
  absl::StatusOr<TMesh> mesh = TMeshFromProto(proto->get());
  if (!mesh.ok()) {
    return absl::Status(mesh.status().code(), absl::StrCat(path, ": ", mesh.status().message()));
  }
  return MeshFile{*std::move(proto), *std::move(mesh)};
}

absl::StatusOr<TMesh> LoadMeshModel(const std::string& path) { return ReadTMeshModelFile(path); }

}  // namespace ispq::cli
