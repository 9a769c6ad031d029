// SPDX-License-Identifier: Apache-2.0
// A fixed number of worker threads, each taking one job at a time from the queue and running it
// to its end (server/jobs/job_runner.h), from a JobSource (server/jobs/job_source.h). A job never
// uses more than its one worker thread, so the pool's size is the number of solves that run at
// once. Threads exit when the queue is closed and empty; the destructor joins them.
#ifndef ISPQ_SERVER_JOBS_WORKER_POOL_H_
#define ISPQ_SERVER_JOBS_WORKER_POOL_H_

#include <thread>
#include <vector>

#include "server/jobs/job_source.h"
#include "server/metrics/server_metrics.h"

namespace ispq::server {

class WorkerPool {
 public:
  // Starts `workers` threads; `source` and `metrics` must outlive the pool.
  WorkerPool(int workers, JobSource& source, ServerMetrics& metrics);
  // Joins the threads: close the source first, or this waits forever.
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int size() const { return static_cast<int>(threads_.size()); }

 private:
  void Work();

  JobSource& source_;
  ServerMetrics& metrics_;
  std::vector<std::thread> threads_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_WORKER_POOL_H_
