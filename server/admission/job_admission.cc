// SPDX-License-Identifier: Apache-2.0
#include "server/admission/job_admission.h"

#include <algorithm>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/proto/quantization_proto.h"
#include "server/memory/memory_estimates.h"
#include "server/model/mesh_admission.h"
#include "server/model/resource_names.h"

namespace ispq::server {
namespace {

// A report interval from the request: unset gives `unset`, zero gives zero, negative or
// malformed durations are rejected, and positive ones are raised to kMinReportInterval.
absl::StatusOr<absl::Duration> ReportInterval(const char* field, bool present,
                                              const google::protobuf::Duration& duration,
                                              absl::Duration unset) {
  if (!present) return unset;
  // Negative, or not a valid Duration (nanos must stay below one second).
  if (duration.seconds() < 0 || duration.nanos() < 0 || duration.nanos() >= 1'000'000'000) {
    return absl::InvalidArgumentError(absl::StrCat(field, " must be a non-negative duration, got ",
                                                   duration.seconds(), "s ", duration.nanos(),
                                                   "ns"));
  }
  const absl::Duration interval =
      absl::Seconds(duration.seconds()) + absl::Nanoseconds(duration.nanos());
  if (interval == absl::ZeroDuration()) return interval;
  return std::max(interval, kMinReportInterval);
}

// The request's own mesh, with memory reserved for it before it is built.
absl::Status AdmitInlineMesh(const v1::TMesh& proto, int64_t request_bytes,
                             const AdmissionContext& context, JobSpec& spec) {
  if (absl::Status size = CheckMeshSize(proto, context.limits.max_arcs); !size.ok()) return size;
  absl::StatusOr<MemoryReservation> memory =
      context.memory.Reserve(MemoryUse::kJobs, MeshBytes(request_bytes), "the mesh");
  if (!memory.ok()) return memory.status();
  absl::StatusOr<AdmittedMesh> admitted =
      AdmitMesh(proto, context.limits.max_arcs, *std::move(memory));
  if (!admitted.ok()) return admitted.status();
  spec.mesh = std::move(admitted->mesh);
  spec.mesh_stats = std::move(admitted->stats);
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::shared_ptr<const StoredMesh>> FindStoredMesh(const std::string& name,
                                                                 const Principal& principal,
                                                                 MeshStore& meshes) {
  absl::StatusOr<std::string> id = ParseResourceName(kMeshCollection, name);
  if (!id.ok()) return id.status();
  std::shared_ptr<const StoredMesh> stored = meshes.Find(*id);
  if (stored == nullptr || !principal.CanAccess(stored->owner)) {
    return absl::NotFoundError(absl::StrCat(
        "stored mesh ", name,
        " not found: it was never created, was deleted, or was evicted; upload it again"));
  }
  return stored;
}

absl::StatusOr<JobSpec> PrepareJobSpec(const v1::QuantizeRequest& request, int64_t request_bytes,
                                       const AdmissionContext& context) {
  JobSpec spec;
  switch (request.mesh_source_case()) {
    case v1::QuantizeRequest::kMesh: {
      absl::Status admitted = AdmitInlineMesh(request.mesh(), request_bytes, context, spec);
      if (!admitted.ok()) return admitted;
      break;
    }
    case v1::QuantizeRequest::kStoredMesh: {
      absl::StatusOr<std::shared_ptr<const StoredMesh>> stored =
          FindStoredMesh(request.stored_mesh(), context.principal, context.meshes);
      if (!stored.ok()) return stored.status();
      spec.mesh = (*stored)->admitted.mesh;
      spec.mesh_stats = (*stored)->admitted.stats;
      spec.stored_mesh = request.stored_mesh();
      break;
    }
    case v1::QuantizeRequest::MESH_SOURCE_NOT_SET:
      return absl::InvalidArgumentError("no mesh given: set mesh or stored_mesh");
  }

  absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(request.options(), *spec.mesh);
  if (!options.ok()) return options.status();
  spec.options = *options;
  const double max_seconds = absl::ToDoubleSeconds(context.limits.max_job_time);
  spec.options.time_limit_seconds = std::min(spec.options.time_limit_seconds, max_seconds);
  spec.requested_options = request.options();

  absl::StatusOr<absl::Duration> progress =
      ReportInterval("progress_interval", request.has_progress_interval(),
                     request.progress_interval(), kDefaultProgressInterval);
  if (!progress.ok()) return progress.status();
  spec.progress_interval = std::max(*progress, kMinReportInterval);
  absl::StatusOr<absl::Duration> intermediate =
      ReportInterval("intermediate_interval", request.has_intermediate_interval(),
                     request.intermediate_interval(), absl::ZeroDuration());
  if (!intermediate.ok()) return intermediate.status();
  spec.intermediate_interval = *intermediate;
  spec.owner = context.principal.name;
  spec.request_id = request.request_id();

  // Last, once the request is known to be valid: the solver's working memory.
  absl::StatusOr<MemoryReservation> working = context.memory.Reserve(
      MemoryUse::kJobs, SolverBytes(SolveSizeOf(spec.mesh_stats, spec.options)),
      "the job's solver working memory");
  if (!working.ok()) return working.status();
  spec.memory = *std::move(working);
  return spec;
}

}  // namespace ispq::server
