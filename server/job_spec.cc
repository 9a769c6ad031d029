#include "server/job_spec.h"

#include <algorithm>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/proto/quantization_proto.h"
#include "server/mesh_admission.h"
#include "server/resource_names.h"

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

}  // namespace

absl::StatusOr<JobSpec> PrepareJobSpec(const v1::QuantizeRequest& request, const JobLimits& limits,
                                       MeshStore& meshes) {
  JobSpec spec;
  switch (request.mesh_source_case()) {
    case v1::QuantizeRequest::kMesh: {
      absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(request.mesh(), limits.max_arcs);
      if (!admitted.ok()) return admitted.status();
      spec.mesh = std::move(admitted->mesh);
      spec.mesh_stats = std::move(admitted->stats);
      break;
    }
    case v1::QuantizeRequest::kStoredMesh: {
      absl::StatusOr<std::string> id = ParseResourceName(kMeshCollection, request.stored_mesh());
      if (!id.ok()) return id.status();
      std::shared_ptr<const StoredMesh> stored = meshes.Find(*id);
      if (stored == nullptr) {
        return absl::NotFoundError(absl::StrCat(
            "stored mesh ", request.stored_mesh(),
            " not found: it was never created, was deleted, or was evicted; upload it again"));
      }
      spec.mesh = stored->admitted.mesh;
      spec.mesh_stats = stored->admitted.stats;
      spec.stored_mesh = request.stored_mesh();
      break;
    }
    case v1::QuantizeRequest::MESH_SOURCE_NOT_SET:
      return absl::InvalidArgumentError("no mesh given: set mesh or stored_mesh");
  }

  absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(request.options(), *spec.mesh);
  if (!options.ok()) return options.status();
  spec.options = *options;
  const double max_seconds = absl::ToDoubleSeconds(limits.max_job_time);
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
  return spec;
}

}  // namespace ispq::server
