#include "server/postgres_job_store.h"

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
#include "server/postgres_job_rows.h"
#include "server/postgres_schema.h"
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
      PostgresConnections::Connect(options.uri, options.connections);
  if (!connections.ok()) return connections.status();
  if (absl::Status migrated = MigratePostgresSchema(**connections); !migrated.ok()) {
    return migrated;
  }
  std::unique_ptr<PostgresJobStore> store(
      new PostgresJobStore(std::move(options), *std::move(connections)));
  PostgresJobStore* const self = store.get();
  store->listener_ = std::make_unique<PostgresListener>(
      self->options_.uri,
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
  stopping_.Notify();
  if (lease_thread_.joinable()) lease_thread_.join();
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
  job->SetEventSink(recorder_);
  absl::MutexLock lock(&mutex_);
  EraseExpired(local_);
  local_[job->id()] = job;
  return job;
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
    spdlog::warn("event=job_cancel_failed job={} error=\"{}\"", job.name(),
                 std::string(status.message()));
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
  if (!status.ok())
    spdlog::warn("event=job_count_failed error=\"{}\"", std::string(status.message()));
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
    spdlog::warn("event=job_claim_failed error=\"{}\"", std::string(status.message()));
    return std::nullopt;
  }
  return claim;
}

void PostgresJobStore::Adopt(std::shared_ptr<Job> runner) {
  runner->SetEventSink(recorder_);
  {
    absl::MutexLock lock(&mutex_);
    EraseExpired(local_);
    local_[runner->id()] = runner;
  }
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

void PostgresJobStore::Release(const std::string& id) {
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    work.exec_params(
        "UPDATE ispq_jobs SET state = 1, lease_owner = NULL, lease_expires = NULL "
        "WHERE id = $1 AND lease_owner = $2 AND state = 2",
        id, options_.replica);
    NotifyJobQueued(work);
    NotifyJobChanged(work, id);
    work.commit();
  });
  if (!status.ok()) spdlog::warn("event=job_release_failed job={}", id);
}

void PostgresJobStore::Fail(const std::string& id, const absl::Status& failure) {
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    EndStoredJob(work, id, failure, absl::Now());
    work.commit();
  });
  if (!status.ok()) spdlog::warn("event=job_fail_failed job={}", id);
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
  // The runs to check, taken before the renewal: a job claimed after the renewal's snapshot is
  // leased to us but not renewed this time, and must not be taken for a lost one.
  std::vector<std::shared_ptr<Job>> running;
  for (std::shared_ptr<Job>& job : ActiveJobs()) {
    if (job->state() == v1::RUNNING) running.push_back(std::move(job));
  }
  std::vector<std::string> renewed;
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    renewed.clear();
    pqxx::work work(connection);
    for (const pqxx::row& row : work.exec_params(
             "UPDATE ispq_jobs SET lease_expires = now() + $2::bigint * interval '1 millisecond' "
             "WHERE lease_owner = $1 AND state IN (1, 2) RETURNING id",
             options_.replica, Milliseconds(options_.lease))) {
      renewed.push_back(row[0].as<std::string>());
    }
    work.commit();
  });
  if (!status.ok()) {
    spdlog::warn("event=lease_renewal_failed error=\"{}\"", std::string(status.message()));
    return;
  }
  std::sort(renewed.begin(), renewed.end());
  for (const std::shared_ptr<Job>& job : running) {
    // A run whose lease is not ours any more: another replica runs the job; stop duplicating.
    // (Its records are refused anyway: they need the lease.)
    if (!job->done() && !std::binary_search(renewed.begin(), renewed.end(), job->id())) {
      spdlog::warn("event=job_lease_lost job={}", job->name());
      job->RequestCancel();
    }
  }
}

void PostgresJobStore::EndOrphanedCallJobs() {
  const absl::Status status = connections_->Run([&](pqxx::connection& connection) {
    pqxx::work work(connection);
    const pqxx::result orphans = work.exec(
        "SELECT id FROM ispq_jobs WHERE bound_to_call AND state IN (1, 2) AND "
        "lease_expires < now() LIMIT 100 FOR UPDATE SKIP LOCKED");
    for (const pqxx::row& row : orphans) {
      EndStoredJob(work, row[0].as<std::string>(),
                   absl::UnavailableError("the replica serving this job's Quantize call stopped; "
                                          "the call ended with it"),
                   absl::Now());
    }
    work.commit();
  });
  if (!status.ok())
    spdlog::warn("event=orphan_sweep_failed error=\"{}\"", std::string(status.message()));
}

void PostgresJobStore::MaintainLeases() {
  const absl::Duration period = options_.lease / 3;
  absl::Time next_prune = absl::Now();
  while (!stopping_.WaitForNotificationWithTimeout(period)) {
    RenewLeases();
    EndOrphanedCallJobs();
    if (absl::Now() >= next_prune) {
      next_prune = absl::Now() + kPruneEvery;
      const absl::Status pruned = connections_->Run([&](pqxx::connection& connection) {
        pqxx::work work(connection);
        PruneFinishedJobs(work, options_.retention, absl::Now());
        work.commit();
      });
      if (!pruned.ok())
        spdlog::warn("event=prune_failed error=\"{}\"", std::string(pruned.message()));
    }
  }
}

}  // namespace ispq::server
