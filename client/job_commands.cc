// SPDX-License-Identifier: Apache-2.0
#include "client/job_commands.h"

#include <iostream>
#include <string>
#include <utility>

#include "absl/strings/str_format.h"
#include "absl/time/time.h"
#include "client/announced_upload.h"
#include "client/exit_codes.h"
#include "client/job_output.h"
#include "client/message_json.h"
#include "client/quantize_input.h"
#include "client/quantizer_client.h"
#include "google/protobuf/util/time_util.h"

namespace ispq::cli {
namespace {

constexpr int kListPageSize = 200;

absl::StatusOr<client::QuantizerClient> Connect(const RemoteCommandOptions& options) {
  return client::QuantizerClient::Connect(options.connection);
}

std::string FormatTime(const google::protobuf::Timestamp& timestamp) {
  if (timestamp.seconds() == 0 && timestamp.nanos() == 0) return "-";
  return absl::FormatTime("%Y-%m-%dT%H:%M:%SZ", absl::FromUnixSeconds(timestamp.seconds()),
                          absl::UTCTimeZone());
}

std::string OutcomeColumn(const v1::Job& job) {
  if (job.has_result()) {
    return absl::StrFormat("objective %.6g%s", job.result().objective(),
                           job.result().valid() ? "" : " (not valid)");
  }
  if (job.has_error()) return job.error().message();
  if (job.has_latest_progress()) {
    return absl::StrFormat("objective %.6g after %.1fs", job.latest_progress().objective(),
                           job.latest_progress().elapsed_seconds());
  }
  return "";
}

}  // namespace

int RunSubmit(const std::string& mesh_path, const v1::QuantizationOptions& quantization,
              const RemoteCommandOptions& options) {
  QuantizeInputOrExit loaded = LoadQuantizeInput(mesh_path, quantization, MeshUse::kSendToServer);
  if (!loaded.input.has_value()) return loaded.exit_code;
  v1::QuantizeRequest& request = MakeQuantizeRequest(*loaded.input, quantization);
  absl::StatusOr<client::QuantizerClient> client = Connect(options);
  if (!client.ok()) return ReportError(options.connection.address, client.status());
  // The uploaded mesh stays on the server for the job (and for retries of this submission); the
  // server evicts it when it needs room.
  const absl::StatusOr<std::string> uploaded =
      UploadIfLarge(*client, request, options.upload_above_bytes, options.progress);
  if (!uploaded.ok()) return ReportError(options.connection.address, uploaded.status());
  const absl::StatusOr<v1::Job> job = client->SubmitJob(request);
  if (!job.ok()) return ReportError(options.connection.address, job.status());
  if (options.json) {
    std::cout << MessageToJson(*job) << "\n";
  } else {
    std::cout << job->name() << "\n";
  }
  return kExitOk;
}

int RunWatch(const std::string& job, int64_t from_event, const RemoteCommandOptions& options) {
  absl::StatusOr<client::QuantizerClient> client = Connect(options);
  if (!client.ok()) return ReportError(options.connection.address, client.status());
  JobEventPrinter printer(options.progress);
  client::StreamOptions stream;
  stream.timeout = options.deadline;
  stream.on_event = [&printer](const v1::QuantizeEvent& event) { return printer.OnEvent(event); };
  const client::JobOutcome outcome = client->FollowJob(client::JobName(job), from_event, stream);
  printer.Finish();
  return ReportJobOutcome(outcome, options);
}

int RunCancel(const std::string& job, const RemoteCommandOptions& options) {
  absl::StatusOr<client::QuantizerClient> client = Connect(options);
  if (!client.ok()) return ReportError(options.connection.address, client.status());
  const absl::StatusOr<v1::Job> cancelled = client->CancelJob(client::JobName(job));
  if (!cancelled.ok()) return ReportError(client::JobName(job), cancelled.status());
  if (options.json) {
    std::cout << MessageToJson(*cancelled) << "\n";
  } else {
    std::cout << cancelled->name() << " " << v1::JobState_Name(cancelled->state())
              << (cancelled->done() ? "" : " (stops at its next check)") << "\n";
  }
  return kExitOk;
}

int RunListJobs(v1::JobState state, int limit, const RemoteCommandOptions& options) {
  absl::StatusOr<client::QuantizerClient> client = Connect(options);
  if (!client.ok()) return ReportError(options.connection.address, client.status());
  v1::ListJobsResponse all;
  v1::ListJobsRequest request;
  request.set_state(state);
  do {
    const int wanted = limit > 0 ? limit - all.jobs_size() : kListPageSize;
    request.set_page_size(std::min(wanted, kListPageSize));
    const absl::StatusOr<v1::ListJobsResponse> page = client->ListJobs(request);
    if (!page.ok()) return ReportError(options.connection.address, page.status());
    all.mutable_jobs()->MergeFrom(page->jobs());
    request.set_page_token(page->next_page_token());
  } while (!request.page_token().empty() && (limit <= 0 || all.jobs_size() < limit));
  if (options.json) {
    std::cout << MessageToJson(all) << "\n";
    return kExitOk;
  }
  std::cout << absl::StrFormat("%-22s %-10s %-28s %7s  %-20s %s\n", "JOB", "STATE", "MESH", "ARCS",
                               "CREATED", "OUTCOME");
  for (const v1::Job& job : all.jobs()) {
    std::cout << absl::StrFormat("%-22s %-10s %-28.28s %7d  %-20s %s\n", job.name(),
                                 v1::JobState_Name(job.state()), job.mesh_display_name(),
                                 job.mesh_stats().arcs(), FormatTime(job.create_time()),
                                 OutcomeColumn(job));
  }
  return kExitOk;
}

}  // namespace ispq::cli
