// SPDX-License-Identifier: Apache-2.0
#include "client/batch_command.h"

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <thread>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "client/batch_plan.h"
#include "client/batch_progress.h"
#include "client/exit_codes.h"
#include "client/mesh_file_input.h"
#include "client/quantizer_client.h"
#include "client/result_output.h"
#include "core/proto/quantization_proto.h"

namespace ispq::cli {
namespace {

namespace fs = std::filesystem;

// How one job of the batch ended.
struct BatchOutcome {
  std::string job;  // "jobs/{id}" on the server that ran it; "" if never submitted
  std::optional<v1::QuantizationResult> result;
  absl::Status status;  // OK for a valid result, written
  bool kept = false;    // a valid result file was there already
};

// Codes after which the same call may work later: the server is away, restarting or full.
bool MayWorkLater(const absl::Status& status) {
  switch (status.code()) {
    case absl::StatusCode::kUnavailable:
    case absl::StatusCode::kResourceExhausted:
    case absl::StatusCode::kDeadlineExceeded:
    case absl::StatusCode::kAborted:
    case absl::StatusCode::kInternal:
    case absl::StatusCode::kUnknown:
      return true;
    default:
      return false;
  }
}

std::string ProgressText(const v1::QuantizeEvent& event) {
  if (event.has_accepted()) return absl::StrFormat("%s accepted", event.job());
  const v1::Progress* progress = event.has_progress()       ? &event.progress()
                                 : event.has_intermediate() ? &event.intermediate().progress()
                                                            : nullptr;
  if (progress == nullptr) return event.job();
  return absl::StrFormat("%s %s objective %.6g after %.1fs", event.job(),
                         v1::Phase_Name(progress->phase()), progress->objective(),
                         progress->elapsed_seconds());
}

// Runs one job to its end through whatever the server goes through (see the header).
class BatchJobRunner {
 public:
  BatchJobRunner(client::QuantizerClient& client, BatchProgress& progress, absl::Duration patience,
                 int64_t upload_above_bytes)
      : client_(client),
        progress_(progress),
        patience_(patience),
        upload_above_bytes_(upload_above_bytes) {}

  BatchOutcome Run(int index, const BatchJob& job) {
    BatchOutcome outcome;
    if (absl::StatusOr<v1::QuantizationResult> kept = ReadResultFile(job.result_path);
        kept.ok() && kept->valid()) {
      outcome.result = *kept;
      outcome.kept = true;
      return outcome;
    }
    absl::StatusOr<v1::QuantizeRequest> request = MakeRequest(job);
    if (!request.ok()) {
      outcome.status = request.status();
      return outcome;
    }
    request->set_request_id(BatchRequestId(*request, fs::absolute(job.result_path).string()));
    client::JobOutcome followed = Follow(index, job, *request);
    outcome.job = followed.job;
    outcome.status = followed.status;
    outcome.result = std::move(followed.result);
    if (outcome.status.ok() && outcome.result.has_value()) {
      if (!outcome.result->valid()) {
        outcome.status = absl::FailedPreconditionError("the result is not valid");
      } else {
        std::error_code ignored;
        fs::create_directories(fs::path(job.result_path).parent_path(), ignored);
        outcome.status = WriteResultFile(job.result_path, *outcome.result);
      }
    }
    return outcome;
  }

 private:
  // The request for `job`, checked here as `ispq quantize` checks it: INVALID_ARGUMENT with the
  // file's problem (naming the offending element) or the option's.
  static absl::StatusOr<v1::QuantizeRequest> MakeRequest(const BatchJob& job) {
    absl::StatusOr<MeshFile> file = LoadMeshFile(job.mesh_path);
    if (!file.ok()) return absl::InvalidArgumentError(file.status().message());
    if (absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(job.options, file->mesh);
        !options.ok()) {
      return absl::InvalidArgumentError(
          absl::StrCat(job.mesh_path, ": ", options.status().message()));
    }
    v1::QuantizeRequest request;
    request.mutable_mesh()->Swap(file->proto.mutable_message());
    *request.mutable_options() = job.options;
    return request;
  }

  // Submits (again, under the same request id, when the server lost the job) and follows the
  // job until it ends or the server stays away for `patience_`.
  client::JobOutcome Follow(int index, const BatchJob& job, const v1::QuantizeRequest& request) {
    std::string stored_mesh;  // the uploaded mesh of a large request
    client::JobOutcome outcome = FollowUntilEnd(index, job, request, stored_mesh);
    if (!stored_mesh.empty()) (void)client_.DeleteMesh(stored_mesh);  // its job is over
    return outcome;
  }

  // One submission. A large mesh is uploaded first (UploadMesh) and the request sent with its
  // name; if the server no longer has it (restarted), it is uploaded again on the next try.
  absl::StatusOr<std::string> Submit(const v1::QuantizeRequest& request, std::string& stored_mesh) {
    const bool large = request.mesh().ByteSizeLong() > static_cast<size_t>(upload_above_bytes_);
    if (!large) {
      absl::StatusOr<v1::Job> job = client_.SubmitJob(request);
      if (!job.ok()) return job.status();
      return job->name();
    }
    if (stored_mesh.empty()) {
      absl::StatusOr<v1::Mesh> uploaded = client_.UploadMesh(request.mesh());
      if (!uploaded.ok()) return uploaded.status();
      stored_mesh = uploaded->name();
    }
    v1::QuantizeRequest by_name;
    by_name.set_stored_mesh(stored_mesh);
    *by_name.mutable_options() = request.options();
    by_name.set_request_id(request.request_id());
    absl::StatusOr<v1::Job> job = client_.SubmitJob(by_name);
    if (job.ok()) return job->name();
    if (job.status().code() != absl::StatusCode::kNotFound) return job.status();
    stored_mesh.clear();
    return absl::UnavailableError(
        absl::StrCat("the server no longer has the uploaded mesh (", job.status().message(), ")"));
  }

  client::JobOutcome FollowUntilEnd(int index, const BatchJob& job,
                                    const v1::QuantizeRequest& request, std::string& stored_mesh) {
    absl::Time last_answer = absl::Now();
    absl::Duration backoff = absl::Milliseconds(100);
    std::string name;
    int64_t next_event = 0;
    while (true) {
      absl::Status failure;
      if (name.empty()) {
        absl::StatusOr<std::string> submitted = Submit(request, stored_mesh);
        if (submitted.ok()) {
          name = *submitted;
          next_event = 0;
        } else {
          failure = submitted.status();
        }
      }
      if (!name.empty()) {
        client::StreamOptions stream;
        stream.on_event = [&](const v1::QuantizeEvent& event) {
          progress_.Update(index, job.name, ProgressText(event));
          return true;
        };
        client::JobOutcome outcome = client_.FollowJob(name, next_event, stream, 2);
        if (outcome.job_ended || outcome.status.ok()) return outcome;
        next_event = outcome.next_event;
        failure = outcome.status;
        if (failure.code() == absl::StatusCode::kNotFound) {
          progress_.Notice(index, job.name,
                           absl::StrCat(name, " is gone from the server: submitting it again"));
          name.clear();
          last_answer = absl::Now();  // NOT_FOUND is an answer: the server is back
          continue;
        }
      }
      if (!MayWorkLater(failure) || absl::Now() - last_answer > patience_) {
        client::JobOutcome gave_up;
        gave_up.job = name;
        gave_up.status = failure;
        return gave_up;
      }
      progress_.Notice(
          index, job.name,
          absl::StrFormat("%s; retrying in %s", failure.message(), absl::FormatDuration(backoff)));
      absl::SleepFor(backoff);
      backoff = std::min(backoff * 2, absl::Seconds(5));
    }
  }

  client::QuantizerClient& client_;
  BatchProgress& progress_;
  const absl::Duration patience_;
  const int64_t upload_above_bytes_;
};

std::string OutcomeText(const BatchOutcome& outcome) {
  if (!outcome.status.ok()) return std::string(outcome.status.message());
  return absl::StrFormat("objective %.6g%s", outcome.result->objective(),
                         outcome.kept ? " (kept from an earlier run)" : "");
}

absl::Status WriteSummary(const std::string& path, const std::vector<BatchJob>& jobs,
                          const std::vector<BatchOutcome>& outcomes) {
  std::ofstream out(path);
  out << "mesh\tscaling\tstate\tobjective\thexes\tsolve_seconds\tjob\tresult_or_error\n";
  for (size_t i = 0; i < jobs.size(); ++i) {
    const BatchOutcome& o = outcomes[i];
    const bool ok = o.status.ok();
    out << jobs[i].mesh_path << "\t" << ScalingLabel(jobs[i].options.scaling()) << "\t"
        << (ok ? (o.kept ? "KEPT" : "SUCCEEDED") : "FAILED") << "\t"
        << (ok ? absl::StrFormat("%.17g", o.result->objective()) : "") << "\t"
        << (ok ? absl::StrCat(o.result->hexes()) : "") << "\t"
        << (ok ? absl::StrFormat("%.3f", o.result->stats().solve_seconds()) : "") << "\t" << o.job
        << "\t" << (ok ? jobs[i].result_path : std::string(o.status.message())) << "\n";
  }
  out.close();
  if (!out) return absl::InternalError(absl::StrCat("cannot write ", path));
  return absl::OkStatus();
}

}  // namespace

int RunBatch(const BatchCommandOptions& batch, const RemoteCommandOptions& options) {
  absl::StatusOr<std::vector<BatchJob>> jobs =
      PlanBatch(batch.inputs, batch.variants, batch.out_dir);
  if (!jobs.ok()) {
    std::cerr << "ispq: batch: " << jobs.status().message() << "\n";
    return kExitInvalidInput;
  }
  std::error_code error;
  fs::create_directories(batch.out_dir, error);
  if (error) {
    std::cerr << "ispq: batch: cannot create " << batch.out_dir << ": " << error.message() << "\n";
    return kExitFailed;
  }
  absl::StatusOr<client::QuantizerClient> client =
      client::QuantizerClient::Connect(options.connection);
  if (!client.ok()) {
    std::cerr << "ispq: batch: " << client.status().message() << "\n";
    return ExitCodeFor(client.status());
  }
  BatchProgress progress(stderr, static_cast<int>(jobs->size()), options.progress);
  std::vector<BatchOutcome> outcomes(jobs->size());
  std::atomic<size_t> next{0};
  auto work = [&] {
    BatchJobRunner runner(*client, progress, batch.patience, options.upload_above_bytes);
    for (size_t i = next++; i < jobs->size(); i = next++) {
      outcomes[i] = runner.Run(static_cast<int>(i), (*jobs)[i]);
      progress.Finished(static_cast<int>(i), (*jobs)[i].name, outcomes[i].status.ok(),
                        OutcomeText(outcomes[i]));
    }
  };
  std::vector<std::thread> workers;
  for (int w = 0; w < std::max(1, batch.concurrency); ++w) workers.emplace_back(work);
  for (std::thread& worker : workers) worker.join();
  progress.Close();

  const std::string summary_path = (fs::path(batch.out_dir) / "summary.tsv").string();
  std::vector<std::string> failed;
  int exit_code = kExitOk;
  std::cout << absl::StrFormat("%-44s %-10s %-14s %s\n", "JOB", "STATE", "OBJECTIVE", "RESULT");
  for (size_t i = 0; i < jobs->size(); ++i) {
    const BatchOutcome& o = outcomes[i];
    std::cout << absl::StrFormat(
        "%-44s %-10s %-14s %s\n", (*jobs)[i].name,
        o.status.ok() ? (o.kept ? "KEPT" : "SUCCEEDED") : "FAILED",
        o.status.ok() ? absl::StrFormat("%.6g", o.result->objective()) : "",
        o.status.ok() ? (*jobs)[i].result_path : o.status.message());
    if (o.status.ok()) continue;
    failed.push_back((*jobs)[i].name + (o.job.empty() ? "" : " (" + o.job + ")"));
    const bool invalid = o.result.has_value() && !o.result->valid();
    if (exit_code == kExitOk) exit_code = invalid ? kExitInvalidResult : ExitCodeFor(o.status);
  }
  if (absl::Status written = WriteSummary(summary_path, *jobs, outcomes); !written.ok()) {
    std::cerr << "ispq: batch: " << written.message() << "\n";
    if (exit_code == kExitOk) exit_code = kExitFailed;
  }
  if (!failed.empty()) {
    std::cerr << "ispq: batch: " << failed.size() << " of " << jobs->size()
              << " jobs have no valid result: " << absl::StrJoin(failed, ", ") << "\n";
  }
  return exit_code;
}

}  // namespace ispq::cli
