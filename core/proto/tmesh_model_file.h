// SPDX-License-Identifier: Apache-2.0
// The core model of a T-mesh file, for callers that need the model only (a local solve, `ispq
// stats`, `ispq validate`, the benchmarks). The message is never held whole where the encoding
// allows it: a binary file is decoded straight from the file in two passes
// (core/proto/tmesh_from_wire.h), so loading takes the model and one element's message, not the
// parsed message beside the model (at 101k arcs a 182 MiB peak, 118 MiB of it the message). A JSON
// file is parsed into its message first (protobuf's JSON parser makes nothing smaller), which is
// freed before this returns.
//
// Callers that send the message on (a remote `ispq quantize`) read it with core/proto/tmesh_file.h.
#ifndef ISPQ_CORE_PROTO_TMESH_MODEL_FILE_H_
#define ISPQ_CORE_PROTO_TMESH_MODEL_FILE_H_

#include <string>

#include "absl/status/statusor.h"
#include "core/tmesh.h"

namespace ispq {

// Binary if the name ends in ".pb" or ".binpb", JSON otherwise, as ReadTMeshFile decides. NOT_FOUND
// if the file cannot be opened; INVALID_ARGUMENT if it is larger than kMaxTMeshFileBytes, does not
// parse, or is no valid T-mesh. Every message starts with the path and names what is wrong.
absl::StatusOr<TMesh> ReadTMeshModelFile(const std::string& path);

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_TMESH_MODEL_FILE_H_
