// SPDX-License-Identifier: Apache-2.0
// The input of `ispq quantize` and `ispq submit`: the T-mesh file read and validated, and the
// quantization flags resolved against it. Both the local and the remote path start here, so a
// bad file or flag fails with the same message and exit code in both modes, and a remote
// command fails before any round trip. (The server validates again: it trusts no client.)
#ifndef ISPQ_CLIENT_QUANTIZE_INPUT_H_
#define ISPQ_CLIENT_QUANTIZE_INPUT_H_

#include <optional>
#include <string>

#include "core/proto/tmesh_file.h"
#include "core/quantizer.h"
#include "core/tmesh.h"
#include "ispq/v1/quantization.pb.h"
#include "ispq/v1/service.pb.h"

namespace ispq::cli {

// Where the mesh goes: a server needs the message as read, a local solve the model only.
enum class MeshUse { kSendToServer, kSolveHere };

struct QuantizeInput {
  TMeshMessage proto;  // as read for kSendToServer; empty for kSolveHere
  TMesh mesh;          // validated
  QuantizeOptions options;
};

struct QuantizeInputOrExit {
  std::optional<QuantizeInput> input;
  int exit_code = 0;  // when there is no input; the problem was printed on stderr
};

QuantizeInputOrExit LoadQuantizeInput(const std::string& mesh_path,
                                      const v1::QuantizationOptions& quantization, MeshUse use);

// The request for a server: `input`'s mesh moves into it without a copy (the request is made on
// the mesh's arena, and lives as long as `input`).
v1::QuantizeRequest& MakeQuantizeRequest(QuantizeInput& input,
                                         const v1::QuantizationOptions& quantization);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_QUANTIZE_INPUT_H_
