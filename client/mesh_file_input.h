// SPDX-License-Identifier: Apache-2.0
// A T-mesh file as every CLI command takes it: read (JSON or binary protobuf), then decoded and
// checked into the model. One place, so that `quantize`, `submit`, `validate` and `stats` refuse
// a bad file with the same message and the same exit code. A command that sends the mesh to a
// server needs its message too (LoadMeshFile); one that solves or checks here needs the model
// only (LoadMeshModel), which a binary file gives without the message's memory. The two decode
// with the same checks and errors; for bytes that are no protobuf at all the model's says where
// they break.
#ifndef ISPQ_CLIENT_MESH_FILE_INPUT_H_
#define ISPQ_CLIENT_MESH_FILE_INPUT_H_

#include <string>

#include "absl/status/statusor.h"
#include "core/proto/tmesh_file.h"
#include "core/tmesh.h"

namespace ispq::cli {

struct MeshFile {
  TMeshMessage proto;  // as read, for sending to a server
  TMesh mesh;          // validated
};

// The error names the file and the offending element; the caller prints it and exits with
// kExitInvalidInput.
absl::StatusOr<MeshFile> LoadMeshFile(const std::string& path);
absl::StatusOr<TMesh> LoadMeshModel(const std::string& path);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_MESH_FILE_INPUT_H_
