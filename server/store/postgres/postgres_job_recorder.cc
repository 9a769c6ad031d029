// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/postgres_job_recorder.h"

#include <algorithm>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "core/invariant.h"
#include "google/protobuf/util/time_util.h"
#include "server/logging/log_value.h"
#include "server/store/postgres/postgres_job_rows.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

constexpr absl::Duration kFirstRetry = absl::Milliseconds(100);
constexpr absl::Duration kMaxRetry = absl::Seconds(5);

int KindIndex(const v1::QuantizeEvent& event) { return static_cast<int>(EventKind(event)); }

}  // namespace

PostgresJobRecorder::PostgresJobRecorder(std::shared_ptr<PostgresConnections> connections,
                                         std::string replica, RetentionPolicy retention)
    : connections_(std::move(connections)),
      replica_(std::move(replica)),
      retention_(retention),
      writer_([this] { WriteLoop(); }) {}

void PostgresJobRecorder::Stop() {
  {
    absl::MutexLock lock(&mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  writer_.join();
  absl::MutexLock lock(&mutex_);
  for (const auto& [id, record] : pending_) {
    if (record.dirty) {
      spdlog::warn(
          "event=job_record_dropped job=jobs/{} attempt={} reason=\"stopped before the "
          "job store took it; its lease expires and another replica runs it again\"",
          id, record.attempt);
    }
  }
  pending_.clear();
}

void PostgresJobRecorder::Track(const std::shared_ptr<Job>& job, int attempt) {
  std::shared_ptr<Job> superseded;
  bool superseded_bound = false;
  {
    absl::MutexLock lock(&mutex_);
    Pending& record = pending_[job->id()];
    // This replica claimed the job again (its earlier lease expired while it stalled): the
    // earlier run's records would be written under the new lease; it must stop.
    superseded = record.job.lock();
    superseded_bound = record.bound_to_call;
    ISPQ_INVARIANT(record.run == nullptr || attempt > record.attempt,
                   "each claim of a job has a higher attempt than the one it supersedes");
    record = Pending();
    record.job = job;
    record.run = job.get();
    record.attempt = attempt;
    record.bound_to_call = job->bound_to_call();
  }
  if (superseded != nullptr && superseded != job) AbandonRun(superseded, superseded_bound);
}

void PostgresJobRecorder::Record(Job& job, const v1::QuantizeEvent* event) {
  // Taken outside the lock: the job's own lock nests inside nothing of ours.
  v1::Job summary = RowSummary(job);
  const bool interrupted_for_drain =
      draining_ && event != nullptr && EventKind(*event) == StoredEventKind::kTerminal &&
      (!event->has_result() || event->result().termination() == v1::INTERRUPTED);
  absl::MutexLock lock(&mutex_);
  const auto it = pending_.find(job.id());
  // Not ours (any more) to record, or an earlier run of a job claimed again.
  if (stopping_ || it == pending_.end() || it->second.run != &job) return;
  Pending& record = it->second;
  record.summary = std::move(summary);
  if (event != nullptr) record.events[KindIndex(*event)] = *event;
  record.release = interrupted_for_drain && !record.bound_to_call;
  record.dirty = true;
  ++record.version;
  record.next_try = absl::InfinitePast();  // new news: write it now, whatever the backoff
}

std::vector<JobLease> PostgresJobRecorder::Leases() const {
  std::vector<JobLease> leases;
  absl::MutexLock lock(&mutex_);
  leases.reserve(pending_.size());
  for (const auto& [id, record] : pending_) leases.push_back({id, record.attempt});
  return leases;
}

void PostgresJobRecorder::LeaseLost(const JobLease& lease) {
  std::shared_ptr<Job> job;
  bool bound_to_call = false;
  {
    absl::MutexLock lock(&mutex_);
    const auto it = pending_.find(lease.id);
    if (it == pending_.end() || it->second.attempt != lease.attempt) return;  // ended, or anew
    job = it->second.job.lock();
    bound_to_call = it->second.bound_to_call;
    pending_.erase(it);
  }
  spdlog::warn("event=job_lease_lost job=jobs/{} attempt={}", lease.id, lease.attempt);
  if (job != nullptr) AbandonRun(job, bound_to_call);
}

void PostgresJobRecorder::AbandonRun(const std::shared_ptr<Job>& job, bool bound_to_call) {
  // Another replica runs a claimed job now; a call-bound job's lease is taken only by the sweep
  // that ends it when its replica looks dead (server/store/postgres/postgres_job_store.h).
  job->Abandon(absl::UnavailableError(
      bound_to_call ? "the job store ended this job: its replica did not renew the lease in time "
                      "(the database was unreachable); submit it again"
                    : "another replica runs this job now"));
}

bool PostgresJobRecorder::Flush(absl::Time deadline) {
  absl::MutexLock lock(&mutex_);
  auto written = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
    return stopping_ || std::none_of(pending_.begin(), pending_.end(),
                                     [](const auto& entry) { return entry.second.dirty; });
  };
  return mutex_.AwaitWithDeadline(absl::Condition(&written), deadline);
}

void PostgresJobRecorder::WriteLoop() {
  while (true) {
    std::vector<std::pair<std::string, Pending>> due;
    {
      absl::MutexLock lock(&mutex_);
      // Wakes for a new record (Record clears next_try) or the earliest retry.
      absl::Time wake = absl::InfiniteFuture();
      auto ready = [&]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) {
        if (stopping_) return true;
        const absl::Time now = absl::Now();
        wake = absl::InfiniteFuture();
        for (const auto& [id, record] : pending_) {
          if (!record.dirty) continue;
          if (record.next_try <= now) return true;
          wake = std::min(wake, record.next_try);
        }
        return false;
      };
      while (!ready()) mutex_.AwaitWithDeadline(absl::Condition(&ready), wake);
      if (stopping_) return;
      const absl::Time now = absl::Now();
      for (const auto& [id, record] : pending_) {
        if (record.dirty && record.next_try <= now) due.emplace_back(id, record);
      }
    }
    for (const auto& [id, record] : due) Settle(id, record, Write(id, record));
  }
}

void PostgresJobRecorder::Settle(const std::string& id, const Pending& written, Written outcome) {
  std::shared_ptr<Job> abandoned;
  bool bound_to_call = false;
  {
    absl::MutexLock lock(&mutex_);
    const auto it = pending_.find(id);
    if (it == pending_.end() || it->second.run != written.run) return;
    Pending& record = it->second;
    switch (outcome) {
      case Written::kDone:
        record.backoff = absl::ZeroDuration();
        if (record.version != written.version) return;  // newer news: write again
        if (written.release || written.summary.done()) {
          pending_.erase(it);  // ended or given back: nothing more to record
          return;
        }
        record.dirty = false;
        for (std::optional<v1::QuantizeEvent>& event : record.events) event.reset();
        return;
      case Written::kFailed:
        record.backoff = std::clamp(2 * record.backoff, kFirstRetry, kMaxRetry);
        record.next_try = absl::Now() + record.backoff;
        return;
      case Written::kLeaseLost:
        abandoned = record.job.lock();
        bound_to_call = record.bound_to_call;
        pending_.erase(it);
        break;
    }
  }
  spdlog::warn(
      "event=job_lease_lost job=jobs/{} attempt={} reason=\"the store refused the write: "
      "another replica holds the job now\"",
      id, written.attempt);
  if (abandoned != nullptr) AbandonRun(abandoned, bound_to_call);
}

std::optional<PostgresJobRecorder::Written> PostgresJobRecorder::Release(const std::string& id,
                                                                         const Pending& record) {
  std::optional<Written> outcome;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "UPDATE ispq_jobs SET state = $4, lease_owner = NULL, lease_expires = NULL "
        "WHERE id = $1 AND lease_owner = $2 AND attempts = $3 AND state IN (1, 2) "
        "AND NOT cancel_requested RETURNING id",
        id, replica_, record.attempt, static_cast<int>(v1::QUEUED));
    if (rows.empty()) return;  // cancelled meanwhile (its end is written), or not ours
    NotifyJobChanged(work, id);
    NotifyJobQueued(work);
    work.commit();
    outcome = Written::kDone;
  });
  if (!status.ok()) return Written::kFailed;
  if (outcome.has_value()) spdlog::info("event=job_released job=jobs/{} reason=shutdown", id);
  return outcome;
}

PostgresJobRecorder::Written PostgresJobRecorder::Write(const std::string& id,
                                                        const Pending& record) {
  if (record.release) {
    if (std::optional<Written> released = Release(id, record)) return *released;
  }
  const v1::Job& summary = record.summary;
  const bool done = summary.done();
  const int64_t end_ns =
      done ? google::protobuf::util::TimeUtil::TimestampToNanoseconds(summary.end_time()) : 0;
  bool fenced_out = false;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    fenced_out = false;
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "UPDATE ispq_jobs SET state = $4, summary = $5, next_sequence = $6, "
        "end_time_ns = CASE WHEN $7::boolean THEN $8::bigint ELSE NULL END, "
        "request = CASE WHEN $7::boolean THEN NULL ELSE request END, "
        "lease_owner = CASE WHEN $7::boolean THEN NULL ELSE lease_owner END, "
        "lease_expires = CASE WHEN $7::boolean THEN NULL ELSE lease_expires END "
        "WHERE id = $1 AND lease_owner = $2 AND attempts = $3 AND state IN (1, 2) RETURNING id",
        id, replica_, record.attempt, static_cast<int>(summary.state()), ProtoBytes(summary),
        summary.event_count(), done, end_ns);
    if (rows.empty()) {
      fenced_out = true;
      return;  // rolled back
    }
    for (const std::optional<v1::QuantizeEvent>& event : record.events) {
      if (event.has_value()) StoreEvent(work, id, *event);
    }
    NotifyJobChanged(work, id);
    if (done) PruneFinishedJobs(work, retention_, absl::FromUnixNanos(end_ns));
    work.commit();
  });
  if (!status.ok()) {
    if (const auto held_back = failures_.Admit()) {
      spdlog::warn(
          "event=job_record_failed job=jobs/{} error={} suppressed={} "
          "retry=\"until written or the lease is gone\"",
          id, QuotedLogValue(std::string(status.message())), *held_back);
    }
    return Written::kFailed;
  }
  return fenced_out ? Written::kLeaseLost : Written::kDone;
}

}  // namespace ispq::server
