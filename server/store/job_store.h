// SPDX-License-Identifier: Apache-2.0
// Every job the server can answer about: all queued and running jobs, and finished jobs while
// the retention policy keeps them (at most `max_finished` of them, none older than `max_age`
// after it ended; the oldest-ended go first). The interface has two implementations:
//
//   * InMemoryJobStore (server/store/in_memory_job_store.h), the default: the job objects of this
//     process, lost when it exits.
//   * PostgresJobStore (server/store/postgres/postgres_job_store.h): jobs and their kept events in
//   PostgreSQL,
//     shared by every replica using the same database; jobs are claimed from it by any replica's
//     workers under a lease (server/jobs/job_claimer.h).
//
// Both are thread-safe. Times are passed in, so that retention is testable.
#ifndef ISPQ_SERVER_STORE_JOB_STORE_H_
#define ISPQ_SERVER_STORE_JOB_STORE_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "ispq/v1/service.pb.h"
#include "server/model/job.h"

namespace ispq::server {

struct RetentionPolicy {
  int max_finished = 1000;
  absl::Duration max_age = absl::Hours(1);
};

class JobStore {
 public:
  virtual ~JobStore() = default;

  // Records a job just admitted, before it is answered for or run. `request` is the serialized
  // QuantizeRequest it was admitted from: a shared store keeps it so that any replica can run the
  // job. Returns the job to answer with: `job` itself, or, for a request_id its owner already
  // used with the same request fingerprint (JobSpec::request_fingerprint), the job that request
  // created; ALREADY_EXISTS for the same id with another request; UNAVAILABLE if the store
  // cannot be reached.
  virtual absl::StatusOr<std::shared_ptr<Job>> Add(std::shared_ptr<Job> job,
                                                   const std::string& request, absl::Time now) = 0;
  // nullptr if the job is unknown or no longer retained (or the store cannot be reached).
  virtual std::shared_ptr<Job> Find(const std::string& id, absl::Time now) = 0;
  // As Find, but tells an unknown job (OK, nullptr) from a store that cannot answer
  // (UNAVAILABLE), so that a client is never told a job does not exist when it may.
  virtual absl::StatusOr<std::shared_ptr<Job>> Lookup(const std::string& id, absl::Time now) {
    return Find(id, now);
  }

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
  virtual absl::StatusOr<Page> List(const Query& query, absl::Time now) = 0;

  // Asks the job to stop wherever it runs. A shared store also ends a job still queued in it
  // (CANCELLED) and tells the replica that runs it; the in-memory store leaves both to the
  // scheduler, which holds the queue.
  virtual void Cancel(Job& job, absl::Time now) = 0;

  // Drops the finished job that ended first; false if no job has finished.
  virtual bool EvictOldestFinished() = 0;

  // Jobs that have not ended and run or wait on this replica.
  virtual std::vector<std::shared_ptr<Job>> ActiveJobs() const = 0;
  virtual v1::JobCounts CountByState() const = 0;

  // Whether other replicas share this store: jobs are then claimed from it, not only queued here.
  virtual bool shared() const = 0;
  // Whether the store answers now (cheap: a flag, never a round trip). A store in this process
  // always does.
  virtual bool reachable() const { return true; }
  // Waits until what jobs reported is durably stored, at most until `deadline`; whether it is.
  virtual bool Flush(absl::Time /*deadline*/) { return true; }
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_JOB_STORE_H_
