// SPDX-License-Identifier: Apache-2.0
// The default job store (server/store/job_store.h): the job objects of this process, in admission
// order. Pruning happens on each access, so no timer thread is needed and memory is bounded by
// the queue, the workers and the retention policy; the memory budget may also evict the
// oldest-ended job early (EvictOldestFinished). Nothing survives the process.
#ifndef ISPQ_SERVER_STORE_IN_MEMORY_JOB_STORE_H_
#define ISPQ_SERVER_STORE_IN_MEMORY_JOB_STORE_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/container/btree_map.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "server/store/job_store.h"

namespace ispq::server {

class InMemoryJobStore final : public JobStore {
 public:
  explicit InMemoryJobStore(RetentionPolicy policy);

  // Never refuses: request ids are resolved before, by server/admission/request_ids.h.
  absl::StatusOr<std::shared_ptr<Job>> Add(std::shared_ptr<Job> job, const std::string& request,
                                           absl::Time now) override;
  std::shared_ptr<Job> Find(const std::string& id, absl::Time now) override;
  absl::StatusOr<Page> List(const Query& query, absl::Time now) override;
  void Cancel(Job& job, absl::Time now) override;
  bool EvictOldestFinished() override;
  std::vector<std::shared_ptr<Job>> ActiveJobs() const override;
  v1::JobCounts CountByState() const override;
  bool shared() const override { return false; }

 private:
  void PruneLocked(absl::Time now) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  const RetentionPolicy policy_;
  mutable absl::Mutex mutex_;
  uint64_t next_ordinal_ ABSL_GUARDED_BY(mutex_) = 0;
  // By admission order, so that listing newest first and page tokens are simple.
  absl::btree_map<uint64_t, std::shared_ptr<Job>> by_ordinal_ ABSL_GUARDED_BY(mutex_);
  absl::flat_hash_map<std::string, uint64_t> ordinal_by_id_ ABSL_GUARDED_BY(mutex_);
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_IN_MEMORY_JOB_STORE_H_
