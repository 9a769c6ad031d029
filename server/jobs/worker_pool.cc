// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/worker_pool.h"

#include <memory>

#include "server/jobs/job_runner.h"
#include "server/jobs/thread_priority.h"
#include "server/memory/memory_release.h"

namespace ispq::server {

WorkerPool::WorkerPool(int workers, JobSource& source, ServerMetrics& metrics)
    : source_(source), metrics_(metrics) {
  threads_.reserve(workers);
  for (int i = 0; i < workers; ++i) threads_.emplace_back([this] { Work(); });
}

WorkerPool::~WorkerPool() {
  for (std::thread& thread : threads_) thread.join();
}

void WorkerPool::Work() {
  LowerCurrentThreadPriority();
  while (std::shared_ptr<Job> job = source_.Next()) {
    RunJob(*job, metrics_);
    job.reset();  // drop the worker's reference before the queue counts the job as done
    source_.Done();
    ReleaseFreedMemory();  // what the solve freed, before the next job fragments it further
  }
}

}  // namespace ispq::server
