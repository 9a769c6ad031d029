// SPDX-License-Identifier: Apache-2.0
// The shared, durable job store (server/store/job_store.h) on PostgreSQL, selected with
// --job_store=postgresql://...: every replica using the same database sees every job.
//
//   * Add commits the job's row (with its serialized request) and its accepted event before the
//     job is answered for; a request_id already used by the same owner on any replica returns
//     that job (a unique index settles races between replicas).
//   * Jobs are not queued in one process: the workers of any replica claim them
//     (JobClaims, `FOR UPDATE SKIP LOCKED`) under a lease of `lease` that a thread of the store
//     renews every third of it for the jobs this replica still runs or has yet to record the
//     end of (server/store/postgres/postgres_job_recorder.h). A job whose lease expired (its
//     replica died or stalled) is claimed again and run from the start elsewhere, with its event
//     numbers continuing; every write is fenced by the claim's attempt number, so the replica that
//     lost the lease can no longer write anything. Call-bound jobs (Quantize) are leased to their
//     replica at once and run there only; if that replica stops renewing for a whole lease
//     beyond the expiry, they end UNAVAILABLE (their call died with it).
//   * Find and List answer with mirrors (Job::Mirror) built from the rows. A mirror that someone
//     holds (a watcher) is kept up to date: every change of a job is NOTIFYed, and a listener
//     thread (server/store/postgres/postgres_listener.h) reloads the mirrors of changed jobs, which
//     wake their watchers. So a WatchJob on any replica streams the job live.
//   * Cancel ends a job still queued in the database at once and otherwise marks it; the
//     replica running it hears of it (NOTIFY) and interrupts its run.
//   * Retention as in memory: finished jobs beyond the count or the age are deleted, when a job
//     ends and periodically. EvictOldestFinished is not used by the memory budget here: retained
//     results live in the database, not in this process.
//   * Faults: every operation is bounded in time (server/store/postgres/postgres_connections.h);
//   the recorder
//     retries what it could not write; reachable() says whether the database answers
//     (server/store/postgres/postgres_reachability.h) for readiness. Failures are logged at most
//     every 10 s per kind.
//
// Ownership: the store owns its connection pool (shared with the recorder that the jobs it
// records hold), its recorder's writer, its listener, its probe and its lease thread; mirrors
// and local jobs are held weakly.
#ifndef ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_STORE_H_
#define ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_STORE_H_

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "server/logging/log_throttle.h"
#include "server/store/job_claims.h"
#include "server/store/job_store.h"
#include "server/store/postgres/postgres_connections.h"
#include "server/store/postgres/postgres_job_recorder.h"
#include "server/store/postgres/postgres_listener.h"
#include "server/store/postgres/postgres_reachability.h"

namespace ispq::server {

struct PostgresJobStoreOptions {
  std::string uri;  // postgresql://user:password@host:port/database?...
  RetentionPolicy retention;
  absl::Duration lease = absl::Seconds(30);
  int connections = 8;
  // The longest one database operation may take (server/store/postgres/postgres_connections.h).
  absl::Duration operation_timeout = absl::Seconds(10);
  // How often reachability is probed, and how long a probe waits for its answer.
  absl::Duration probe_period = absl::Seconds(1);
  absl::Duration probe_timeout = absl::Seconds(2);
  std::string replica;  // this replica's name in leases; empty: host name, pid and a random part
};

class PostgresJobStore final : public JobStore, public JobClaims {
 public:
  // Connects, migrates the schema (server/store/postgres/postgres_schema.h) and starts listening.
  // INVALID_ARGUMENT for a URI that is not postgresql:// or postgres://, UNAVAILABLE if the
  // database cannot be reached, FAILED_PRECONDITION for a newer schema.
  static absl::StatusOr<std::unique_ptr<PostgresJobStore>> Open(PostgresJobStoreOptions options);
  // Stops the lease thread, the listener and the recorder (Flush first). Jobs still running
  // here lose their lease and are run again elsewhere.
  ~PostgresJobStore() override;

  // ---- JobStore ----
  absl::StatusOr<std::shared_ptr<Job>> Add(std::shared_ptr<Job> job, const std::string& request,
                                           absl::Time now) override;
  std::shared_ptr<Job> Find(const std::string& id, absl::Time now) override;
  absl::StatusOr<std::shared_ptr<Job>> Lookup(const std::string& id, absl::Time now) override;
  absl::StatusOr<Page> List(const Query& query, absl::Time now) override;
  void Cancel(Job& job, absl::Time now) override;
  bool EvictOldestFinished() override;
  std::vector<std::shared_ptr<Job>> ActiveJobs() const override;
  v1::JobCounts CountByState() const override;
  bool shared() const override { return true; }
  bool reachable() const override { return reachability_->reachable(); }
  bool Flush(absl::Time deadline) override { return recorder_->Flush(deadline); }

  // ---- JobClaims ----
  std::optional<Claim> ClaimNext() override;
  void Adopt(std::shared_ptr<Job> runner, const Claim& claim) override;
  void Release(const Claim& claim) override;
  void Fail(const Claim& claim, const absl::Status& status) override;
  int QueuedCount() override;
  void OnClaimable(std::function<void()> wake) override;
  void BeginDraining() override { recorder_->BeginDraining(); }
  absl::Duration poll_interval() const override;

  const std::string& replica() const { return options_.replica; }
  // The store's connections, shared with the mesh store
  // (server/store/postgres/postgres_mesh_store.h).
  const std::shared_ptr<PostgresConnections>& connections() const { return connections_; }

 private:
  PostgresJobStore(PostgresJobStoreOptions options,
                   std::shared_ptr<PostgresConnections> connections);

  // The mirror of `id`, registered so that notifications keep it up to date; nullptr if unknown,
  // UNAVAILABLE if the database cannot be reached.
  absl::StatusOr<std::shared_ptr<Job>> LoadMirror(const std::string& id, absl::Time now);
  // Reloads the registered mirror of `id`, if anyone still holds it.
  void Refresh(const std::string& id);
  void OnNotification(const std::string& channel, const std::string& payload);
  void Wake();
  // Registers a job created or run here (cancellation notices, shutdown).
  void AddLocal(const std::shared_ptr<Job>& job);
  // The lease thread: renews this replica's leases, abandons runs whose lease was lost, ends
  // call-bound jobs whose replica died, prunes retention. Woken early when the database answers
  // again after an outage, so that leases are renewed before other replicas take them.
  void MaintainLeases();
  void RenewLeases();
  void EndOrphanedCallJobs();
  void PruneRetention();

  const PostgresJobStoreOptions options_;
  const std::shared_ptr<PostgresConnections> connections_;
  const std::shared_ptr<PostgresJobRecorder> recorder_;

  mutable absl::Mutex mutex_;
  absl::flat_hash_map<std::string, std::weak_ptr<Job>> mirrors_ ABSL_GUARDED_BY(mutex_);
  size_t sweep_mirrors_at_ ABSL_GUARDED_BY(mutex_) = 256;
  // Jobs created or run here: interrupted at shutdown, told of cancellations.
  absl::flat_hash_map<std::string, std::weak_ptr<Job>> local_ ABSL_GUARDED_BY(mutex_);
  std::function<void()> wake_ ABSL_GUARDED_BY(mutex_);
  bool renew_now_ ABSL_GUARDED_BY(mutex_) = false;
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;

  // One per kind of recurring failure line.
  LogThrottle claim_failures_{absl::Seconds(10)};
  LogThrottle lease_failures_{absl::Seconds(10)};
  LogThrottle sweep_failures_{absl::Seconds(10)};
  mutable LogThrottle query_failures_{absl::Seconds(10)};  // CountByState is const

  std::unique_ptr<PostgresReachability> reachability_;
  std::unique_ptr<PostgresListener> listener_;  // started last, stopped first
  std::thread lease_thread_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_POSTGRES_POSTGRES_JOB_STORE_H_
