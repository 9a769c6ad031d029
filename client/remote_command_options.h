// SPDX-License-Identifier: Apache-2.0
// What every `ispq` subcommand that talks to a server shares: where the server is and how to
// reach it, the call's deadline, and how to show the outcome (the same flags as the local path).
#ifndef ISPQ_CLIENT_REMOTE_COMMAND_OPTIONS_H_
#define ISPQ_CLIENT_REMOTE_COMMAND_OPTIONS_H_

#include <cstdint>
#include <string>

#include "absl/time/time.h"
#include "client/quantizer_client.h"
#include "client/server_connection.h"

namespace ispq::cli {

struct RemoteCommandOptions {
  client::ServerConnection connection;
  absl::Duration deadline = absl::InfiniteDuration();  // of a streaming call (quantize, watch)
  bool json = false;                                   // machine-readable output on stdout
  bool progress = true;                                // live progress on stderr
  std::string out_path;                                // result file, if any
  // Meshes larger than this are uploaded in chunks (UploadMesh) before the job is sent.
  int64_t upload_above_bytes = client::QuantizerClient::kUploadAboveBytes;
};

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_REMOTE_COMMAND_OPTIONS_H_
