// SPDX-License-Identifier: Apache-2.0
#include "server/store/postgres/postgres_job_store.h"

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <utility>

#include "absl/random/random.h"
#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "google/protobuf/util/time_util.h"
#include "server/logging/log_value.h"
#include "server/store/postgres/postgres_job_rows.h"
#include "server/store/postgres/postgres_schema.h"
#include "spdlog/spdlog.h"

namespace ispq::server {
namespace {

constexpr int kDefaultPageSize = 50;
constexpr int kMaxPageSize = 1000;
constexpr absl::Duration kPruneEvery = absl::Seconds(10);

std::string DefaultReplicaName() {
  char host[256] = {};
  gethostname(host, sizeof(host) - 1);
  absl::BitGen random;
  return absl::StrCat(host, "/", getpid(), "/", absl::Uniform<uint32_t>(random));
}

// Drops the entries of jobs nobody holds any more.
void EraseExpired(absl::flat_hash_map<std::string, std::weak_ptr<Job>>& jobs) {
  for (auto it = jobs.begin(); it != jobs.end();) {
    if (it->second.expired()) {
      jobs.erase(it++);
    } else {
      ++it;
    }
  }
}

std::string Milliseconds(absl::Duration duration) {
  return absl::StrCat(absl::ToInt64Milliseconds(duration));
}

}  // namespace

absl::StatusOr<std::unique_ptr<PostgresJobStore>> PostgresJobStore::Open(
    PostgresJobStoreOptions options) {
  if (!absl::StartsWith(options.uri, "postgresql://") &&
      !absl::StartsWith(options.uri, "postgres://")) {
    return absl::InvalidArgumentError(
        "--job_store must be \"memory\" or a postgresql://... connection URI");
  }
  if (options.lease < absl::Milliseconds(300)) {
    return absl::InvalidArgumentError("the job lease must be at least 0.3 s");
  }
  if (options.replica.empty()) options.replica = DefaultReplicaName();
  absl::StatusOr<std::shared_ptr<PostgresConnections>> connections =
      PostgresConnections::Connect({.uri = options.uri,
                                    .size = options.connections,
                                    .operation_timeout = options.operation_timeout});
  if (!connections.ok()) return connections.status();
  if (absl::Status migrated = MigratePostgresSchema(**connections); !migrated.ok()) {
    return migrated;
  }
  std::unique_ptr<PostgresJobStore> store(
      new PostgresJobStore(std::move(options), *std::move(connections)));
  PostgresJobStore* const self = store.get();
  store->reachability_ = std::make_unique<PostgresReachability>(
      *self->connections_, self->options_.probe_period, self->options_.probe_timeout, [self] {
        absl::MutexLock lock(&self->mutex_);
        self->renew_now_ = true;
      });
  store->listener_ = std::make_unique<PostgresListener>(
      self->connections_->uri(),
      std::vector<std::string>{kJobChangedChannel, kJobQueuedChannel, kJobCancelChannel},
      [self](const std::string& channel, const std::string& payload) {
        self->OnNotification(channel, payload);
      });
  store->lease_thread_ = std::thread([self] { self->MaintainLeases(); });
  spdlog::info("event=job_store_open kind=postgresql replica={} lease_seconds={}",
               self->options_.replica, absl::ToDoubleSeconds(self->options_.lease));
  return store;
}

PostgresJobStore::PostgresJobStore(PostgresJobStoreOptions options,
                                   std::shared_ptr<PostgresConnections> connections)
    : options_(std::move(options)),
      connections_(std::move(connections)),
      recorder_(std::make_shared<PostgresJobRecorder>(connections_, options_.replica,
                                                      options_.retention)) {}

PostgresJobStore::~PostgresJobStore() {
  listener_.reset();
  {
    absl::MutexLock lock(&mutex_);
    stopping_ = true;
  }
  if (lease_thread_.joinable()) lease_thread_.join();
  reachability_.reset();
  recorder_->Stop();
}

// ---------------------------------------------------------------------------------------------
// JobStore

absl::StatusOr<std::shared_ptr<Job>> PostgresJobStore::Add(std::shared_ptr<Job> job,
                                                           const std::string& request,
                                                           absl::Time now) {
  const JobSpec& spec = job->spec();
  const v1::Job summary = RowSummary(*job);
  const std::optional<v1::QuantizeEvent> accepted = job->NextForStream(0).event;
  std::optional<std::string> existing;  // the job an earlier call with the request id created
  bool different_request = false;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result inserted = work.exec_params(
        "INSERT INTO ispq_jobs (id, owner, request_id, fingerprint, bound_to_call, state, summary, "
        "request, create_time_ns, next_sequence, lease_owner, lease_expires) "
        "VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, "
        "CASE WHEN $5::boolean THEN $11::text ELSE NULL END, "
        "CASE WHEN $5::boolean THEN now() + $12::bigint * interval '1 millisecond' ELSE NULL END) "
        "ON CONFLICT (owner, request_id) WHERE request_id <> '' DO NOTHING RETURNING id",
        job->id(), spec.owner, spec.request_id, pqxx::binarystring(spec.request_fingerprint),
        job->bound_to_call(), static_cast<int>(v1::QUEUED), ProtoBytes(summary),
        pqxx::binarystring(request), absl::ToUnixNanos(now), summary.event_count(),
        options_.replica, Milliseconds(options_.lease));
    if (inserted.empty()) {
      const pqxx::result earlier = work.exec_params(
          "SELECT id, fingerprint FROM ispq_jobs WHERE owner = $1 AND request_id = $2", spec.owner,
          spec.request_id);
      if (earlier.empty()) throw std::runtime_error("a request id vanished while being read");
      existing = earlier[0][0].as<std::string>();
      different_request = pqxx::binarystring(earlier[0][1]).str() != spec.request_fingerprint;
      return;
    }
    if (accepted.has_value()) StoreEvent(work, job->id(), *accepted);
    if (!job->bound_to_call()) NotifyJobQueued(work);
    work.commit();
  });
  if (!status.ok()) return status;
  if (existing.has_value()) {
    if (different_request) {
      return absl::AlreadyExistsError(absl::StrCat("request_id ", spec.request_id,
                                                   " was already used for a different request"));
    }
    absl::StatusOr<std::shared_ptr<Job>> earlier = LoadMirror(*existing, now);
    if (!earlier.ok()) return earlier.status();
    if (*earlier == nullptr) {
      return absl::UnavailableError("the job of this request_id ended meanwhile; retry");
    }
    return earlier;
  }
  if (job->bound_to_call()) {
    // Leased to this replica at creation (attempt 0), run here: recorded from now on. A job
    // queued for any replica is recorded by whoever claims it.
    recorder_->Track(job, /*attempt=*/0);
    job->SetEventSink(recorder_);
  }
  AddLocal(job);
  return job;
}

void PostgresJobStore::AddLocal(const std::shared_ptr<Job>& job) {
  absl::MutexLock lock(&mutex_);
  EraseExpired(local_);
  local_[job->id()] = job;
}

absl::StatusOr<std::shared_ptr<Job>> PostgresJobStore::LoadMirror(const std::string& id,
                                                                  absl::Time now) {
  std::optional<StoredJob> stored;
  const absl::Time retained_since = now - options_.retention.max_age;
  auto load = [&](pqxx::connection& connection) {
    pqxx::work work(connection);
    stored = LoadStoredJob(work, id, retained_since);
  };
  if (absl::Status loaded = connections_->Run(load); !loaded.ok()) return loaded;
  if (!stored.has_value()) return nullptr;
  std::shared_ptr<Job> mirror;
  bool created = false;
  {
    absl::MutexLock lock(&mutex_);
    auto it = mirrors_.find(id);
    if (it != mirrors_.end()) mirror = it->second.lock();
    if (mirror == nullptr) {
      mirror = Job::Mirror(stored->summary, stored->events);
      mirrors_[id] = mirror;
      created = true;
      if (mirrors_.size() >= sweep_mirrors_at_) {
        EraseExpired(mirrors_);
        sweep_mirrors_at_ = std::max<size_t>(256, 2 * mirrors_.size());
      }
    }
  }
  if (!created) {
    mirror->ApplyStored(stored->summary, std::move(stored->events));
  } else {
    // A change committed between the load and the registration notified nobody: look again.
    stored.reset();
    if (connections_->Run(load).ok() && stored.has_value()) {
      mirror->ApplyStored(stored->summary, std::move(stored->events));
    }
  }
  return mirror;
}

std::shared_ptr<Job> PostgresJobStore::Find(const std::string& id, absl::Time now) {
  absl::StatusOr<std::shared_ptr<Job>> mirror = LoadMirror(id, now);
  return mirror.ok() ? *std::move(mirror) : nullptr;
}

absl::StatusOr<std::shared_ptr<Job>> PostgresJobStore::Lookup(const std::string& id,
                                                              absl::Time now) {
  return LoadMirror(id, now);
}

absl::StatusOr<JobStore::Page> PostgresJobStore::List(const Query& query, absl::Time now) {
  if (query.page_size < 0) {
    return absl::InvalidArgumentError(absl::StrCat("page_size ", query.page_size, " is negative"));
  }
  const int size =
      query.page_size == 0 ? kDefaultPageSize : std::min(query.page_size, kMaxPageSize);
  int64_t start = INT64_MAX;  // the ordinal listing resumes at (inclusive)
  if (!query.page_token.empty() && !absl::SimpleAtoi(query.page_token, &start)) {
    return absl::InvalidArgumentError("page_token is not one this server issued");
  }
  Page page;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    page = Page();
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "SELECT id, ordinal, state, summary FROM ispq_jobs WHERE ordinal <= $1 AND "
        "($2 = 0 OR state = $2) AND (end_time_ns IS NULL OR end_time_ns >= $3) "
        "ORDER BY ordinal DESC",
        start, static_cast<int>(query.state), absl::ToUnixNanos(now - options_.retention.max_age));
    for (const pqxx::row& row : rows) {
      const std::string token = row[1].as<std::string>();
      v1::Job summary;
      const pqxx::binarystring bytes(row[3]);
      summary.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()));
      const auto state = static_cast<v1::JobState>(row[2].as<int>());
      summary.set_state(state);
      summary.set_done(IsTerminal(state));
      if (query.visible && !query.visible(*Job::Mirror(summary, {}))) continue;
      if (static_cast<int>(page.jobs.size()) == size) {
        page.next_page_token = token;
        break;
      }
      std::optional<StoredJob> stored = LoadStoredJob(work, row[0].as<std::string>(),
                                                      absl::InfinitePast(), /*terminal_only=*/true);
      if (!stored.has_value()) continue;
      page.jobs.push_back({Job::Mirror(stored->summary, std::move(stored->events)), token});
    }
  });
  if (!status.ok()) return status;
  return page;
}

void PostgresJobStore::Cancel(Job& job, absl::Time now) {
  job.RequestCancel();  // a local object (a mirror, or the run itself)
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "UPDATE ispq_jobs SET cancel_requested = true WHERE id = $1 AND state IN (1, 2) "
        "RETURNING state, bound_to_call",
        job.id());
    if (rows.empty()) return;  // ended, or unknown
    if (rows[0][0].as<int>() == v1::QUEUED && !rows[0][1].as<bool>()) {
      EndStoredJob(work, job.id(), absl::CancelledError("cancelled while queued"), now);
    } else {
      work.exec_params("SELECT pg_notify($1, $2)", kJobCancelChannel, job.id());
      NotifyJobChanged(work, job.id());
    }
    work.commit();
  });
  if (!status.ok()) {
    if (const auto held_back = query_failures_.Admit()) {
      spdlog::warn("event=job_cancel_failed job={} error={} suppressed={}", job.name(),
                   QuotedLogValue(std::string(status.message())), *held_back);
    }
  }
  Refresh(job.id());  // so that CancelJob answers with the state it caused
}

bool PostgresJobStore::EvictOldestFinished() {
  bool evicted = false;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    evicted =
        !work.exec(
                 "DELETE FROM ispq_jobs WHERE id = (SELECT id FROM ispq_jobs WHERE "
                 "end_time_ns IS NOT NULL ORDER BY end_time_ns, ordinal LIMIT 1) RETURNING id")
             .empty();
    work.commit();
  });
  return status.ok() && evicted;
}

std::vector<std::shared_ptr<Job>> PostgresJobStore::ActiveJobs() const {
  std::vector<std::shared_ptr<Job>> active;
  absl::MutexLock lock(&mutex_);
  for (const auto& [id, weak] : local_) {
    std::shared_ptr<Job> job = weak.lock();
    if (job != nullptr && !job->done()) active.push_back(std::move(job));
  }
  return active;
}

v1::JobCounts PostgresJobStore::CountByState() const {
  v1::JobCounts counts;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    for (const pqxx::row& row : work.exec("SELECT state, count(*) FROM ispq_jobs GROUP BY state")) {
      const int64_t count = row[1].as<int64_t>();
      switch (row[0].as<int>()) {
        case v1::QUEUED:
          counts.set_queued(count);
          break;
        case v1::RUNNING:
          counts.set_running(count);
          break;
        case v1::SUCCEEDED:
          counts.set_succeeded(count);
          break;
        case v1::FAILED:
          counts.set_failed(count);
          break;
        case v1::CANCELLED:
          counts.set_cancelled(count);
          break;
        default:
          break;
      }
    }
  });
  if (!status.ok()) {
    if (const auto held_back = query_failures_.Admit()) {
      spdlog::warn("event=job_count_failed error={} suppressed={}",
                   QuotedLogValue(std::string(status.message())), *held_back);
    }
  }
  return counts;
}

// ---------------------------------------------------------------------------------------------
// JobClaims

std::optional<JobClaims::Claim> PostgresJobStore::ClaimNext() {
  std::optional<Claim> claim;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    claim.reset();
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "UPDATE ispq_jobs SET state = 2, lease_owner = $1, "
        "lease_expires = now() + $2::bigint * interval '1 millisecond', attempts = attempts + 1 "
        "WHERE id = (SELECT id FROM ispq_jobs WHERE state IN (1, 2) AND NOT bound_to_call AND "
        "(state = 1 OR lease_expires < now()) ORDER BY ordinal LIMIT 1 FOR UPDATE SKIP LOCKED) "
        "RETURNING id, request, owner, create_time_ns, next_sequence, cancel_requested, attempts",
        options_.replica, Milliseconds(options_.lease));
    if (rows.empty()) return;
    const pqxx::row row = rows[0];
    Claim claimed;
    claimed.id = row[0].as<std::string>();
    const pqxx::binarystring request(row[1]);
    claimed.request_bytes = static_cast<int64_t>(request.size());
    if (!claimed.request.ParseFromArray(request.data(), static_cast<int>(request.size()))) {
      // It can never run: end it rather than let it block the queue.
      EndStoredJob(work, claimed.id, absl::InternalError("the job's stored request does not parse"),
                   absl::Now());
      work.commit();
      return;
    }
    claimed.owner = row[2].as<std::string>();
    claimed.create_time = absl::FromUnixNanos(row[3].as<int64_t>());
    claimed.next_sequence = row[4].as<int64_t>();
    claimed.cancel_requested = row[5].as<bool>();
    claimed.attempt = row[6].as<int>();
    NotifyJobChanged(work, claimed.id);
    work.commit();
    claim = std::move(claimed);
  });
  if (!status.ok()) {
    if (const auto held_back = claim_failures_.Admit()) {
      spdlog::warn("event=job_claim_failed error={} suppressed={}",
                   QuotedLogValue(std::string(status.message())), *held_back);
    }
    return std::nullopt;
  }
  return claim;
}

void PostgresJobStore::Adopt(std::shared_ptr<Job> runner, const Claim& claim) {
  recorder_->Track(runner, claim.attempt);
  runner->SetEventSink(recorder_);
  AddLocal(runner);
  // A cancellation between the claim and the registration above notified nobody here: look.
  bool cancel_requested = false;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result rows =
        work.exec_params("SELECT cancel_requested FROM ispq_jobs WHERE id = $1", runner->id());
    cancel_requested = !rows.empty() && rows[0][0].as<bool>();
  });
  if (status.ok() && cancel_requested) runner->RequestCancel();
}

void PostgresJobStore::Release(const Claim& claim) {
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result rows = work.exec_params(
        "UPDATE ispq_jobs SET state = 1, lease_owner = NULL, lease_expires = NULL "
        "WHERE id = $1 AND lease_owner = $2 AND attempts = $3 AND state = 2 RETURNING id",
        claim.id, options_.replica, claim.attempt);
    if (rows.empty()) return;  // not ours any more
    NotifyJobQueued(work);
    NotifyJobChanged(work, claim.id);
    work.commit();
  });
  // Not given back: the lease expires and the job is claimable again then.
  if (!status.ok()) spdlog::warn("event=job_release_failed job=jobs/{}", claim.id);
}

void PostgresJobStore::Fail(const Claim& claim, const absl::Status& failure) {
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result ours = work.exec_params(
        "SELECT id FROM ispq_jobs WHERE id = $1 AND lease_owner = $2 AND attempts = $3 "
        "FOR UPDATE",
        claim.id, options_.replica, claim.attempt);
    if (ours.empty()) return;  // another claim decides now
    EndStoredJob(work, claim.id, failure, absl::Now());
    work.commit();
  });
  // Not ended: the lease expires, and whoever claims the job next finds it unrunnable too.
  if (!status.ok()) spdlog::warn("event=job_fail_failed job=jobs/{}", claim.id);
}

int PostgresJobStore::QueuedCount() {
  int queued = -1;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    queued = work.exec("SELECT count(*) FROM ispq_jobs WHERE state = 1 AND NOT bound_to_call")[0][0]
                 .as<int>();
  });
  return status.ok() ? queued : -1;
}

void PostgresJobStore::OnClaimable(std::function<void()> wake) {
  absl::MutexLock lock(&mutex_);
  wake_ = std::move(wake);
}

absl::Duration PostgresJobStore::poll_interval() const {
  return std::min(options_.lease / 4, absl::Seconds(1));
}

// ---------------------------------------------------------------------------------------------
// Notifications and leases

void PostgresJobStore::Wake() {
  std::function<void()> wake;
  {
    absl::MutexLock lock(&mutex_);
    wake = wake_;
  }
  if (wake) wake();
}

void PostgresJobStore::Refresh(const std::string& id) {
  {
    absl::MutexLock lock(&mutex_);
    const auto it = mirrors_.find(id);
    if (it == mirrors_.end() || it->second.expired()) return;
  }
  LoadMirror(id, absl::Now()).IgnoreError();  // a failed refresh waits for the next change
}

void PostgresJobStore::OnNotification(const std::string& channel, const std::string& payload) {
  if (channel == kJobChangedChannel) {
    Refresh(payload);
    return;
  }
  if (channel == kJobQueuedChannel) {
    Wake();
    return;
  }
  if (channel == kJobCancelChannel) {
    std::shared_ptr<Job> local;
    {
      absl::MutexLock lock(&mutex_);
      const auto it = local_.find(payload);
      if (it != local_.end()) local = it->second.lock();
    }
    if (local != nullptr) {
      spdlog::info("event=job_cancel_requested job={} from=\"another replica\"", local->name());
      local->RequestCancel();
    }
    return;
  }
  // Reconnected: anything may have changed meanwhile.
  std::vector<std::string> ids;
  {
    absl::MutexLock lock(&mutex_);
    for (const auto& [id, weak] : mirrors_) {
      if (!weak.expired()) ids.push_back(id);
    }
  }
  for (const std::string& id : ids) Refresh(id);
  Wake();
}

void PostgresJobStore::RenewLeases() {
  const std::vector<JobLease> leases = recorder_->Leases();
  if (leases.empty()) return;
  std::vector<const JobLease*> lost;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    lost.clear();
    pqxx::work work(connection);
    for (const JobLease& lease : leases) {
      const pqxx::result renewed = work.exec_params(
          "UPDATE ispq_jobs SET lease_expires = now() + $4::bigint * interval '1 millisecond' "
          "WHERE id = $1 AND lease_owner = $2 AND attempts = $3 AND state IN (1, 2) RETURNING id",
          lease.id, options_.replica, lease.attempt, Milliseconds(options_.lease));
      if (renewed.empty()) lost.push_back(&lease);
    }
    work.commit();
  });
  if (!status.ok()) {
    if (const auto held_back = lease_failures_.Admit()) {
      spdlog::warn("event=lease_renewal_failed error={} suppressed={}",
                   QuotedLogValue(std::string(status.message())), *held_back);
    }
    return;
  }
  // Not renewed: another replica holds the job now, or its end was written meanwhile (then the
  // recorder no longer lists it and this changes nothing).
  for (const JobLease* lease : lost) recorder_->LeaseLost(*lease);
}

void PostgresJobStore::EndOrphanedCallJobs() {
  // A whole lease of grace beyond the expiry: a replica cut off from the database keeps running
  // its call's job, and renews the lease as soon as it can reach the database again.
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result orphans = work.exec_params(
        "SELECT id FROM ispq_jobs WHERE bound_to_call AND state IN (1, 2) AND "
        "lease_expires < now() - $1::bigint * interval '1 millisecond' "
        "LIMIT 100 FOR UPDATE SKIP LOCKED",
        Milliseconds(options_.lease));
    for (const pqxx::row& row : orphans) {
      EndStoredJob(work, row[0].as<std::string>(),
                   absl::UnavailableError("the replica serving this job's Quantize call stopped; "
                                          "the call ended with it"),
                   absl::Now());
    }
    work.commit();
  });
  if (!status.ok()) {
    if (const auto held_back = sweep_failures_.Admit()) {
      spdlog::warn("event=orphan_sweep_failed error={} suppressed={}",
                   QuotedLogValue(std::string(status.message())), *held_back);
    }
  }
}

void PostgresJobStore::PruneRetention() {
  const absl::Status pruned = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    PruneFinishedJobs(work, options_.retention, absl::Now());
    work.commit();
  });
  if (!pruned.ok()) {
    if (const auto held_back = sweep_failures_.Admit()) {
      spdlog::warn("event=prune_failed error={} suppressed={}",
                   QuotedLogValue(std::string(pruned.message())), *held_back);
    }
  }
}

void PostgresJobStore::MaintainLeases() {
  const absl::Duration period = options_.lease / 3;
  absl::Time next_prune = absl::Now();
  while (true) {
    {
      absl::MutexLock lock(&mutex_);
      auto woken = [this]()
                       ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return renew_now_ || stopping_; };
      mutex_.AwaitWithTimeout(absl::Condition(&woken), period);
      if (stopping_) return;
      renew_now_ = false;
    }
    RenewLeases();
    EndOrphanedCallJobs();
    if (absl::Now() >= next_prune) {
      next_prune = absl::Now() + kPruneEvery;
      PruneRetention();
    }
  }
}

}  // namespace ispq::server
