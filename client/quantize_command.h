// SPDX-License-Identifier: Apache-2.0
// `ispq quantize FILE (--local | --server HOST:PORT) ...`: reads and validates a T-mesh,
// quantizes it in-process with the same code path a server worker uses, or on a server (the job
// belongs to the call: interrupting the command cancels it), shows live progress and writes the
// result. Both paths take the same flags and write the same result JSON.
#ifndef ISPQ_CLIENT_QUANTIZE_COMMAND_H_
#define ISPQ_CLIENT_QUANTIZE_COMMAND_H_

#include <optional>
#include <string>

#include "client/remote_command_options.h"
#include "ispq/v1/quantization.pb.h"

namespace ispq::cli {

struct QuantizeCommandOptions {
  std::string mesh_path;
  v1::QuantizationOptions quantization;
  std::string out_path;  // empty: no result file
  bool json = false;     // print the result JSON on stdout instead of a summary
  bool progress = true;  // live progress on stderr
};

int RunLocalQuantize(const QuantizeCommandOptions& options);
// `server` supplies the connection and deadline; the output flags come from `options`.
int RunRemoteQuantize(const QuantizeCommandOptions& options, const RemoteCommandOptions& server);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_QUANTIZE_COMMAND_H_
