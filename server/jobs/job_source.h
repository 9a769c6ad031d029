// SPDX-License-Identifier: Apache-2.0
// Where the worker pool takes its jobs from: the local queue (server/jobs/job_queue.h) with the
// in-memory store, or the claimer (server/jobs/job_claimer.h), which also claims jobs from a shared
// store.
#ifndef ISPQ_SERVER_JOBS_JOB_SOURCE_H_
#define ISPQ_SERVER_JOBS_JOB_SOURCE_H_

#include <memory>

#include "server/model/job.h"

namespace ispq::server {

class JobSource {
 public:
  virtual ~JobSource() = default;
  // Blocks until there is a job for the calling worker, which then owns ending it; nullptr once
  // the source is closed and has nothing left: the worker exits.
  virtual std::shared_ptr<Job> Next() = 0;
  // The worker has finished with the job Next gave it.
  virtual void Done() = 0;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_JOB_SOURCE_H_
