// SPDX-License-Identifier: Apache-2.0
// Runs one job to its end on the calling worker thread: the core quantizer
// (core/quantizer.h, single-threaded) with the job's interrupter and a progress publisher, then
// the result or the error into the job, the job's start and end log lines and the metrics.
//
// Never throws and never crashes the server on a failing solve: a solver error or exception
// ends the job FAILED with INTERNAL and the reason.
#ifndef ISPQ_SERVER_JOBS_JOB_RUNNER_H_
#define ISPQ_SERVER_JOBS_JOB_RUNNER_H_

#include "server/metrics/server_metrics.h"
#include "server/model/job.h"

namespace ispq::server {

// `job` was popped from the queue by the calling worker, which owns ending it.
void RunJob(Job& job, ServerMetrics& metrics);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_JOB_RUNNER_H_
