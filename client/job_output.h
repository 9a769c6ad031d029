// SPDX-License-Identifier: Apache-2.0
// How the CLI shows a job that runs on a server: its events while it runs (progress on stderr
// with the same printer as the local path), and its outcome exactly as the local path shows a
// result: the result file, the result JSON or the summary, and the exit code.
#ifndef ISPQ_CLIENT_JOB_OUTPUT_H_
#define ISPQ_CLIENT_JOB_OUTPUT_H_

#include <cstdio>
#include <string>

#include "client/progress_printer.h"
#include "client/quantizer_client.h"
#include "client/remote_command_options.h"
#include "ispq/v1/service.pb.h"

namespace ispq::cli {

// Follows a job's events on stderr: a line when the job is accepted, then live progress.
class JobEventPrinter {
 public:
  explicit JobEventPrinter(bool enabled);

  // An EventHandler (client/quantizer_client.h): never stops the stream.
  bool OnEvent(const v1::QuantizeEvent& event);
  // Ends the progress line before other output.
  void Finish();

 private:
  const bool enabled_;
  ProgressPrinter progress_;
};

// Writes the outcome like the local path (OutputResult in client/result_output.h) and returns the
// exit code: 0 for a valid result, 4 for an invalid one, the error's exit code otherwise.
int ReportJobOutcome(const client::JobOutcome& outcome, const RemoteCommandOptions& options);

// Prints `error` as "ispq: <context>: <message>" and returns its exit code.
int ReportError(const std::string& context, const absl::Status& error);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_JOB_OUTPUT_H_
