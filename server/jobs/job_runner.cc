// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/job_runner.h"

#include <exception>
#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "core/proto/quantization_proto.h"
#include "core/quantizer.h"
#include "server/jobs/progress_publisher.h"
#include "server/logging/log_value.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

absl::StatusOr<QuantizeResult> QuantizeCatchingExceptions(const Job& job,
                                                          ProgressObserver& observer) {
  try {
    return Quantize(*job.spec().mesh, job.spec().options, &observer, &job.interrupter());
  } catch (const std::exception& exception) {
    return absl::InternalError(absl::StrCat("the solver threw: ", exception.what()));
  } catch (...) {
    return absl::InternalError("the solver threw an unknown exception");
  }
}

}  // namespace

void RunJob(Job& job, ServerMetrics& metrics) {
  const absl::Time start = absl::Now();
  if (!job.Start(start)) {
    job.FinishWithError(absl::CancelledError("cancelled before it started"), start);
    metrics.RecordFinished(v1::CANCELLED, -1);
    spdlog::info("event=job_end job={} state=CANCELLED reason=\"cancelled before it started\"",
                 job.name());
    return;
  }
  const JobSpec& spec = job.spec();
  metrics.RecordStarted(start - job.create_time());
  spdlog::info(
      "event=job_start job={} mesh={} arcs={} blocks={} scaling={} queue_wait_ms={:.1f} "
      "bound_to_call={}",
      job.name(), QuotedLogValue(spec.mesh->name()), spec.mesh_stats.arcs(),
      spec.mesh_stats.blocks(), spec.options.scaling,
      absl::ToDoubleMilliseconds(start - job.create_time()), job.bound_to_call());

  ProgressPublisher publisher(job, spec.progress_interval, spec.intermediate_interval);
  absl::StatusOr<QuantizeResult> result = QuantizeCatchingExceptions(job, publisher);
  const absl::Time end = absl::Now();
  const double wall_ms = absl::ToDoubleMilliseconds(end - start);

  if (!result.ok()) {
    const absl::Status status =
        absl::IsInvalidArgument(result.status())
            ? result.status()
            : absl::InternalError(absl::StrCat("quantization failed: ", result.status().message()));
    job.FinishWithError(status, end);
    metrics.RecordFinished(job.state(), -1);
    spdlog::warn("event=job_end job={} state={} wall_ms={:.1f} code={} error={}", job.name(),
                 v1::JobState_Name(job.state()), wall_ms, absl::StatusCodeToString(status.code()),
                 QuotedLogValue(std::string(status.message())));
    return;
  }
  v1::QuantizationResult proto =
      QuantizationResultToProto(*result, spec.options.scaling, *spec.mesh);
  job.FinishWithResult(std::move(proto), end);
  const v1::JobState state = job.state();
  metrics.RecordFinished(state, result->stats.solve_seconds);
  spdlog::info(
      "event=job_end job={} state={} termination={} valid={} objective={} hexes={} solve_ms={:.1f} "
      "wall_ms={:.1f} lp_solves={}",
      job.name(), v1::JobState_Name(state), TerminationName(result->termination), result->valid,
      result->objective, result->hexes, 1000 * result->stats.solve_seconds, wall_ms,
      result->stats.lp_solves);
}

}  // namespace ispq::server
