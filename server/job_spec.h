// What a job is asked to do, fully validated and resolved at admission: the mesh, the core
// options (scaling resolved against the mesh, the time limit capped by the server) and how
// often to report. Everything a client can get wrong is rejected here, before the job exists,
// so that a worker never meets bad input.
#ifndef ISPQ_SERVER_JOB_SPEC_H_
#define ISPQ_SERVER_JOB_SPEC_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "core/quantizer.h"
#include "core/tmesh.h"
#include "ispq/v1/mesh_stats.pb.h"
#include "ispq/v1/quantization.pb.h"
#include "ispq/v1/service.pb.h"
#include "server/mesh_store.h"

namespace ispq::server {

inline constexpr absl::Duration kDefaultProgressInterval = absl::Milliseconds(100);
// Reporting more often than this costs the solver more than any client can use.
inline constexpr absl::Duration kMinReportInterval = absl::Milliseconds(10);

struct JobSpec {
  std::shared_ptr<const TMesh> mesh;
  v1::MeshStats mesh_stats;
  std::string stored_mesh;  // "meshes/{id}" if the request named a stored mesh
  v1::QuantizationOptions requested_options;
  QuantizeOptions options;
  absl::Duration progress_interval = kDefaultProgressInterval;  // at least kMinReportInterval
  absl::Duration intermediate_interval = absl::ZeroDuration();  // zero: none
};

struct JobLimits {
  int max_arcs = 0;
  absl::Duration max_job_time = absl::InfiniteDuration();
};

// INVALID_ARGUMENT for a bad mesh, option or interval; NOT_FOUND for an unknown stored mesh.
absl::StatusOr<JobSpec> PrepareJobSpec(const v1::QuantizeRequest& request, const JobLimits& limits,
                                       MeshStore& meshes);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOB_SPEC_H_
