// SPDX-License-Identifier: Apache-2.0
// The `ispq` subcommands that manage jobs on a server:
//
//   ispq submit FILE --server HOST:PORT (--level P | --scaling S | --target-hexes N) [...]
//        queues a job and prints its name at once
//   ispq watch JOB [--from N] [--out RESULT.json] [--json]
//        follows a job to its end (resuming broken streams) and shows its result like quantize
//   ispq cancel JOB      cancels a job and prints its state
//   ispq jobs [--state STATE] [--limit N] [--json]
//        lists the server's jobs, newest first
//
// JOB is a job name ("jobs/abc") or its bare id ("abc").
#ifndef ISPQ_CLIENT_JOB_COMMANDS_H_
#define ISPQ_CLIENT_JOB_COMMANDS_H_

#include <cstdint>
#include <string>

#include "client/remote_command_options.h"
#include "ispq/v1/quantization.pb.h"
#include "ispq/v1/service.pb.h"

namespace ispq::cli {

int RunSubmit(const std::string& mesh_path, const v1::QuantizationOptions& quantization,
              const RemoteCommandOptions& options);
int RunWatch(const std::string& job, int64_t from_event, const RemoteCommandOptions& options);
int RunCancel(const std::string& job, const RemoteCommandOptions& options);
// `state` JOB_STATE_UNSPECIFIED lists all; `limit` 0 lists every retained job.
int RunListJobs(v1::JobState state, int limit, const RemoteCommandOptions& options);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_JOB_COMMANDS_H_
