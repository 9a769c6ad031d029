// Every job the server can answer about: all queued and running jobs, and finished jobs while
// the retention policy keeps them (at most `max_finished` of them, none older than `max_age`
// after it ended; the oldest-ended go first). Pruning happens on each access, so no timer thread
// is needed and memory is bounded by the queue, the workers and the policy; the memory budget
// may also evict the oldest-ended job early (EvictOldestFinished). Thread-safe.
#ifndef ISPQ_SERVER_JOB_STORE_H_
#define ISPQ_SERVER_JOB_STORE_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/container/btree_map.h"
#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "ispq/v1/service.pb.h"
#include "server/job.h"

namespace ispq::server {

struct RetentionPolicy {
  int max_finished = 1000;
  absl::Duration max_age = absl::Hours(1);
};

class JobStore {
 public:
  explicit JobStore(RetentionPolicy policy);

  void Add(std::shared_ptr<Job> job, absl::Time now);
  // nullptr if the job is unknown or no longer retained.
  std::shared_ptr<Job> Find(const std::string& id, absl::Time now);

  struct Query {
    int page_size = 0;  // 0: the default; clamped to the maximum
    std::string page_token;
    v1::JobState state = v1::JOB_STATE_UNSPECIFIED;  // unspecified: all
    std::function<bool(const Job&)> visible;         // empty: all
  };
  struct Listed {
    std::shared_ptr<Job> job;
    std::string token;  // the page token that resumes listing at this job
  };
  struct Page {
    std::vector<Listed> jobs;     // newest first
    std::string next_page_token;  // empty on the last page
  };
  // INVALID_ARGUMENT for a negative page size or a token this store did not issue.
  absl::StatusOr<Page> List(const Query& query, absl::Time now);

  // Drops the finished job that ended first; false if no job has finished.
  bool EvictOldestFinished();

  // Jobs that have not ended (queued or running).
  std::vector<std::shared_ptr<Job>> ActiveJobs() const;
  v1::JobCounts CountByState() const;

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

#endif  // ISPQ_SERVER_JOB_STORE_H_
