// SPDX-License-Identifier: Apache-2.0
#include "client/job_output.h"

#include <iostream>

#include "client/exit_codes.h"
#include "client/result_output.h"

namespace ispq::cli {

JobEventPrinter::JobEventPrinter(bool enabled) : enabled_(enabled), progress_(stderr) {}

bool JobEventPrinter::OnEvent(const v1::QuantizeEvent& event) {
  if (!enabled_) return true;
  if (event.has_accepted()) {
    const v1::JobAccepted& accepted = event.accepted();
    std::fprintf(stderr, "%s accepted: %s, %d arcs, scaling %g, %d jobs ahead\n",
                 event.job().c_str(), accepted.mesh_display_name().c_str(),
                 accepted.mesh_stats().arcs(), accepted.scaling(), accepted.queue_position());
  } else if (event.has_progress()) {
    progress_.Update(event.progress());
  } else if (event.has_intermediate()) {
    progress_.Update(event.intermediate().progress());
  }
  return true;
}

void JobEventPrinter::Finish() { progress_.Finish(); }

int ReportError(const std::string& context, const absl::Status& error) {
  std::cerr << "ispq: " << context << ": " << error.message() << "\n";
  return ExitCodeFor(error);
}

int ReportJobOutcome(const client::JobOutcome& outcome, const RemoteCommandOptions& options) {
  if (!outcome.result.has_value()) {
    return ReportError(outcome.job.empty() ? options.connection.address : outcome.job,
                       outcome.status);
  }
  return OutputResult(*outcome.result, options.out_path, options.json);
}

}  // namespace ispq::cli
