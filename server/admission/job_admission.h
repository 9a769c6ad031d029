// SPDX-License-Identifier: Apache-2.0
// Admission of a QuantizeRequest as a job's specification (server/model/job_spec.h): the mesh
// (inline, within the memory budget and checked by server/model/mesh_admission.h, or a stored
// mesh the caller may use), the options and report intervals, and the solver's working memory
// reserved (server/admission/memory_admission.h). Everything a client can get wrong is rejected
// here, before the job exists, so that a worker never meets bad input; a job the memory budget
// cannot hold is refused here too.
#ifndef ISPQ_SERVER_ADMISSION_JOB_ADMISSION_H_
#define ISPQ_SERVER_ADMISSION_JOB_ADMISSION_H_

#include <cstdint>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "ispq/v1/service.pb.h"
#include "server/admission/memory_admission.h"
#include "server/auth/principal.h"
#include "server/model/job_spec.h"
#include "server/store/mesh_store.h"

namespace ispq::server {

struct JobLimits {
  int max_arcs = 0;
  absl::Duration max_job_time = absl::InfiniteDuration();
};

// Where a request is admitted from.
struct AdmissionContext {
  const JobLimits& limits;
  const Principal& principal;
  MeshStore& meshes;
  MemoryAdmission& memory;
};

// INVALID_ARGUMENT for a bad mesh, option or interval; NOT_FOUND for an unknown stored mesh (or
// one of another principal); RESOURCE_EXHAUSTED when the memory budget cannot hold the job.
// `request_bytes` is the request's size on the wire, an upper bound of its mesh's.
absl::StatusOr<JobSpec> PrepareJobSpec(const v1::QuantizeRequest& request, int64_t request_bytes,
                                       const AdmissionContext& context);

// The stored mesh `name` if `principal` may use it; INVALID_ARGUMENT for a malformed name,
// NOT_FOUND otherwise (also for another principal's mesh, which is not revealed to exist).
absl::StatusOr<std::shared_ptr<const StoredMesh>> FindStoredMesh(const std::string& name,
                                                                 const Principal& principal,
                                                                 MeshStore& meshes);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_JOB_ADMISSION_H_
