// SPDX-License-Identifier: Apache-2.0
// What a job is asked to do, fully validated and resolved at admission: the mesh, the core
// options (scaling resolved against the mesh, the time limit capped by the server), how often to
// report, who asked, and the memory reserved for it. It is built, and everything a client can get
// wrong rejected, by server/admission/job_admission.h, before the job exists, so that a worker
// never meets bad input.
#ifndef ISPQ_SERVER_MODEL_JOB_SPEC_H_
#define ISPQ_SERVER_MODEL_JOB_SPEC_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "core/quantizer.h"
#include "core/tmesh.h"
#include "ispq/v1/mesh_stats.pb.h"
#include "ispq/v1/quantization.pb.h"
#include "ispq/v1/service.pb.h"
#include "server/memory/memory_budget.h"

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
  std::string owner;       // the principal that submitted the job
  std::string request_id;  // AIP-155, as submitted (may be empty)
  // server/admission/request_fingerprint.h of the request without its id, when request_id is set: a
  // shared store compares it with that of a retry reaching another replica.
  std::string request_fingerprint;
  // The solver's working memory (server/memory/memory_estimates.h), held until the job ends; the
  // mesh's own reservation travels with the mesh.
  MemoryReservation memory;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MODEL_JOB_SPEC_H_
