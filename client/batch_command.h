// SPDX-License-Identifier: Apache-2.0
// `ispq batch`: many meshes (and scalings) through a server with bounded concurrency.
//
//   ispq batch DIR_OR_FILES... (--level P | --levels P,P,... | --scaling S | --target-hexes N)
//        --out-dir DIR [--concurrency N] [--patience SECONDS] [--server ...]
//
// Each job is submitted with a request id derived from its request and result file
// (client/batch_plan.h) and followed to its end. The batch rides out a lost connection or a
// restarting server: a refused or broken call is retried with backoff until `patience` passes
// without an answer; a job the server no longer knows (it restarted without a shared store) is
// submitted again under the same id, so that a server that kept it returns it and none is run
// twice. A valid result is written to its result file (the same JSON as `quantize --out`); a
// result file already there and valid is kept and its job not run again, so an interrupted batch
// is resumed by running the same command. At the end, OUT/summary.tsv and a table on stdout list
// every job; the exit code is 0 only if every job has a valid result, and the failed jobs are
// named on stderr.
#ifndef ISPQ_CLIENT_BATCH_COMMAND_H_
#define ISPQ_CLIENT_BATCH_COMMAND_H_

#include <string>
#include <vector>

#include "absl/time/time.h"
#include "client/remote_command_options.h"
#include "ispq/v1/quantization.pb.h"

namespace ispq::cli {

struct BatchCommandOptions {
  std::vector<std::string> inputs;  // T-mesh files and directories
  // One entry per scaling to run every mesh at (--levels gives several).
  std::vector<v1::QuantizationOptions> variants;
  std::string out_dir;
  int concurrency = 4;  // jobs submitted and followed at once
  absl::Duration patience = absl::Minutes(10);
};

int RunBatch(const BatchCommandOptions& batch, const RemoteCommandOptions& options);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_BATCH_COMMAND_H_
