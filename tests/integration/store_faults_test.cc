// SPDX-License-Identifier: Apache-2.0
// Faults of the shared job store and of replicas, counted exactly (issue 24): a real PostgreSQL
// started by the test (tests/support/postgres_instance.h) that is stopped, restarted and frozen,
// and real ispq-server replicas that are frozen, drained and killed. For every job whose
// submission was acknowledged: it ends exactly once, SUCCEEDED with the q an in-process solve of
// the same request gives (the CLI's --local); every stream that follows it ends with its terminal
// event; no lease outlives the job; and the probes answer as specified during each fault
// (liveness always SERVING, readiness NOT_SERVING while the database is unreachable). What the
// faults cost (log lines, CPU, probe answers) is printed for the record.
//
// No assertion is on wall-clock time: the waits are generous bounds on outcomes.
#include <signal.h>

#include <atomic>
#include <cstdint>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/synchronization/notification.h"
#include "absl/time/clock.h"
#include "client/health_check.h"
#include "core/proto/quantization_proto.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/quantizer.h"
#include "grpcpp/create_channel.h"
#include "grpcpp/security/credentials.h"
#include "gtest/gtest.h"
#include "tests/integration/server_process.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/postgres_instance.h"

namespace ispq::testing {
namespace {

// A lease long enough that a short outage ends within it, short enough that a frozen replica
// loses its jobs quickly; the store's operations time out well within it.
constexpr double kLeaseSeconds = 6;
constexpr double kStoreTimeoutSeconds = 2;
constexpr absl::Duration kProbeTimeout = absl::Seconds(5);  // the manifests' timeoutSeconds
constexpr int kLevels[] = {0, 1, 5, 10, 17, 25, 50, 100};

// q of `request` solved in-process, as `ispq quantize --local` solves it.
std::vector<int32_t> LocalQ(const v1::QuantizeRequest& request) {
  absl::StatusOr<TMesh> mesh = TMeshFromProto(request.mesh());
  EXPECT_TRUE(mesh.ok()) << mesh.status();
  if (!mesh.ok()) return {};
  absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(request.options(), *mesh);
  EXPECT_TRUE(options.ok()) << options.status();
  if (!options.ok()) return {};
  absl::StatusOr<QuantizeResult> result = Quantize(*mesh, *options);
  EXPECT_TRUE(result.ok()) << result.status();
  if (!result.ok()) return {};
  const v1::QuantizationResult proto = QuantizationResultToProto(*result, options->scaling, *mesh);
  return {proto.q().begin(), proto.q().end()};
}

// CPU seconds `pid` has used (user + system), from /proc/PID/stat.
double CpuSeconds(pid_t pid) {
  std::ifstream stat(absl::StrCat("/proc/", pid, "/stat"));
  std::string line;
  std::getline(stat, line);
  // Fields after the command name (which may hold spaces) start after the last ')'.
  const std::vector<std::string> fields =
      absl::StrSplit(line.substr(line.rfind(')') + 2), ' ', absl::SkipEmpty());
  if (fields.size() < 13) return 0;
  return (std::stod(fields[11]) + std::stod(fields[12])) / sysconf(_SC_CLK_TCK);
}

int64_t LineCount(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

// What a series of probes of one replica answered.
struct ProbeCounts {
  int serving = 0;
  int not_serving = 0;
  int failed = 0;  // no answer within the probe timeout, or an error
  std::string Describe() const {
    return absl::StrCat(serving, " SERVING, ", not_serving, " NOT_SERVING, ", failed, " failed");
  }
};

// Probes liveness ("") and readiness of every replica every `period` on a thread of its own,
// as an orchestrator would, until stopped.
class Prober {
 public:
  Prober(std::vector<std::shared_ptr<grpc::Channel>> channels, absl::Duration period)
      : channels_(std::move(channels)),
        liveness_(channels_.size()),
        readiness_(channels_.size()),
        thread_([this, period] { Run(period); }) {}
  ~Prober() { Stop(); }
  void Stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  std::vector<ProbeCounts> liveness() {
    std::lock_guard<std::mutex> lock(mutex_);
    return liveness_;
  }
  std::vector<ProbeCounts> readiness() {
    std::lock_guard<std::mutex> lock(mutex_);
    return readiness_;
  }
  void Reset() {
    std::lock_guard<std::mutex> lock(mutex_);
    liveness_.assign(channels_.size(), {});
    readiness_.assign(channels_.size(), {});
  }

 private:
  static void Count(const absl::StatusOr<client::ServingStatus>& status, ProbeCounts& counts) {
    if (!status.ok()) {
      ++counts.failed;
    } else if (*status == client::ServingStatus::kServing) {
      ++counts.serving;
    } else {
      ++counts.not_serving;
    }
  }
  void Run(absl::Duration period) {
    while (!stop_) {
      for (size_t i = 0; i < channels_.size(); ++i) {
        const auto live = client::CheckHealth(channels_[i], "", kProbeTimeout);
        const auto ready = client::CheckHealth(channels_[i], "readiness", kProbeTimeout);
        std::lock_guard<std::mutex> lock(mutex_);
        Count(live, liveness_[i]);
        Count(ready, readiness_[i]);
      }
      absl::SleepFor(period);
    }
  }

  const std::vector<std::shared_ptr<grpc::Channel>> channels_;
  std::mutex mutex_;
  std::vector<ProbeCounts> liveness_;
  std::vector<ProbeCounts> readiness_;
  std::atomic<bool> stop_ = false;
  std::thread thread_;
};

class StoreFaultsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<std::unique_ptr<PostgresInstance>> started = PostgresInstance::Start();
    ASSERT_TRUE(started.ok()) << started.status();
    postgres_ = *std::move(started);
    absl::StatusOr<std::string> uri = postgres_->CreateDatabase("faults");
    ASSERT_TRUE(uri.ok()) << uri.status();
    uri_ = *uri;
    replicas_.resize(3);  // never resized later: followers read it from their threads
  }
  void TearDown() override {
    StopFollowers();
    if (HasFailure()) {
      for (size_t i = 0; i < replicas_.size(); ++i) {
        if (replicas_[i] != nullptr)
          std::cerr << "---- replica " << i << "\n" << replicas_[i]->Log();
      }
    }
  }

  std::vector<std::string> ReplicaFlags(double lease_seconds, double grace_seconds = 4) const {
    return {absl::StrCat("--job_store=", uri_),
            "--workers=1",
            absl::StrCat("--job_lease_seconds=", lease_seconds),
            absl::StrCat("--job_store_timeout_seconds=", kStoreTimeoutSeconds),
            absl::StrCat("--shutdown_grace_seconds=", grace_seconds),
            "--max_queued_jobs=1000"};
  }
  void StartReplica(size_t index, double lease_seconds = kLeaseSeconds, double grace_seconds = 4) {
    std::unique_ptr<ServerProcess> started =
        StartServerOrFail(ReplicaFlags(lease_seconds, grace_seconds));
    ASSERT_NE(started, nullptr);
    std::lock_guard<std::mutex> lock(mutex_);
    replicas_[index] = std::move(started);
  }
  void StartReplicas(int count, double lease_seconds = kLeaseSeconds) {
    for (int i = 0; i < count; ++i) ASSERT_NO_FATAL_FAILURE(StartReplica(i, lease_seconds));
  }
  client::QuantizerClient Client(size_t index) { return ClientOf(*replicas_[index]); }
  std::vector<std::shared_ptr<grpc::Channel>> Channels() {
    std::vector<std::shared_ptr<grpc::Channel>> channels;
    for (size_t i = 0; i < replicas_.size(); ++i) channels.push_back(Client(i).channel());
    return channels;
  }

  // Submits `request` through replica `index` and follows the job (on a thread of its own,
  // through every replica in turn when a stream breaks) until it ends.
  std::string SubmitAndFollow(size_t index, const v1::QuantizeRequest& request) {
    client::QuantizerClient client = Client(index);
    const absl::StatusOr<v1::Job> job = client.SubmitJob(request);
    EXPECT_TRUE(job.ok()) << job.status();
    if (!job.ok()) return "";
    Acknowledged(job->name(), request);
    Follow(job->name(), index + 1);
    return job->name();
  }
  void Acknowledged(const std::string& job, const v1::QuantizeRequest& request) {
    std::lock_guard<std::mutex> lock(mutex_);
    requests_[job] = request;
  }
  // Follows `job` from `first_replica` on, moving to the next replica whenever a stream breaks
  // (a killed or drained replica, an unreachable store), until the job ends.
  void Follow(const std::string& job, size_t first_replica) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      following_.insert(job);
    }
    followers_.emplace_back([this, job, first_replica] {
      int64_t next_event = 0;
      const absl::Time until = absl::Now() + kJobTimeout;
      for (size_t attempt = 0; !stop_following_ && absl::Now() < until; ++attempt) {
        const size_t index = (first_replica + attempt) % replicas_.size();
        std::optional<client::QuantizerClient> client;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          if (replicas_[index] != nullptr) client = ClientOf(*replicas_[index]);
        }
        if (!client.has_value()) {
          absl::SleepFor(absl::Milliseconds(100));
          continue;
        }
        const client::JobOutcome outcome =
            client->WatchJob(job, next_event, StreamFor(absl::Seconds(60)));
        {
          std::lock_guard<std::mutex> lock(mutex_);
          if (outcome.status.ok() && !outcome.job_ended) ++streams_ended_without_terminal_;
          if (outcome.job_ended) {
            followed_[job] = outcome;
            return;
          }
        }
        next_event = outcome.next_event;
        absl::SleepFor(absl::Milliseconds(100));
      }
      std::lock_guard<std::mutex> lock(mutex_);
      unfinished_follows_.insert(job);
    });
  }
  void StopFollowers() {
    stop_following_ = true;
    for (std::thread& follower : followers_) follower.join();
    followers_.clear();
  }
  void JoinFollowers() {
    for (std::thread& follower : followers_) follower.join();
    followers_.clear();
  }

  // Every acknowledged job ended exactly once, SUCCEEDED with the local q, as every replica and
  // every follower saw it; nothing else is in the store, and no lease is left.
  void ExpectEveryJobEndedOnceWithTheLocalQ() {
    JoinFollowers();
    std::map<std::string, v1::QuantizeRequest> requests;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      requests = requests_;
    }
    std::map<std::string, std::vector<int32_t>> local;  // by serialized request
    for (const auto& [job, request] : requests) {
      const std::string key = request.SerializeAsString();
      if (!local.count(key)) local[key] = LocalQ(request);
      for (size_t i = 0; i < replicas_.size(); ++i) {
        if (replicas_[i] == nullptr || !replicas_[i]->running()) continue;
        client::QuantizerClient client = Client(i);
        const absl::StatusOr<v1::Job> done = WaitUntilDone(client, job);
        ASSERT_TRUE(done.ok()) << job << ": " << done.status();
        EXPECT_EQ(done->state(), v1::SUCCEEDED) << job << " " << done->error().message();
        EXPECT_EQ(done->result().termination(), v1::CONVERGED) << job;
        EXPECT_EQ(absl::StrJoin(done->result().q(), ","), absl::StrJoin(local[key], ","))
            << job << " on replica " << i;
      }
      std::lock_guard<std::mutex> lock(mutex_);
      if (followed_.count(job)) {
        const client::JobOutcome& outcome = followed_[job];
        EXPECT_TRUE(outcome.status.ok()) << job << ": " << outcome.status;
        ASSERT_TRUE(outcome.result.has_value()) << job;
        EXPECT_EQ(absl::StrJoin(outcome.result->q(), ","), absl::StrJoin(local[key], ","));
      } else if (following_.count(job)) {
        ADD_FAILURE() << "its follower did not see " << job << " end";
      }
    }
    EXPECT_EQ(streams_ended_without_terminal_, 0);
    EXPECT_TRUE(unfinished_follows_.empty()) << absl::StrJoin(unfinished_follows_, ", ");
    const absl::StatusOr<std::string> jobs = postgres_->Sql(
        "SELECT count(*) || ' ' || count(*) FILTER (WHERE lease_owner IS NOT NULL) FROM ispq_jobs",
        "faults");
    ASSERT_TRUE(jobs.ok()) << jobs.status();
    EXPECT_EQ(std::string(absl::StripAsciiWhitespace(*jobs)), absl::StrCat(requests.size(), " 0"))
        << "jobs in the store, and jobs still leased";
  }

  // How many of the replicas' log lines lie between two snapshots of their logs.
  std::vector<std::string> LogSnapshots() {
    std::vector<std::string> logs;
    for (const auto& replica : replicas_) logs.push_back(replica ? replica->Log() : "");
    return logs;
  }

  std::unique_ptr<PostgresInstance> postgres_;
  std::string uri_;
  std::vector<std::unique_ptr<ServerProcess>> replicas_;
  std::mutex mutex_;
  std::map<std::string, v1::QuantizeRequest> requests_;  // acknowledged submissions
  std::map<std::string, client::JobOutcome> followed_;   // how each follower saw its job end
  int streams_ended_without_terminal_ = 0;
  std::set<std::string> following_;           // jobs with a follower
  std::set<std::string> unfinished_follows_;  // followers that gave up
  std::atomic<bool> stop_following_ = false;
  std::vector<std::thread> followers_;
};

// The first row of the issue: jobs end while the database is down for less than a lease. Their
// ends are kept and written once it is back; nothing stays RUNNING, no lease is left behind.
TEST_F(StoreFaultsTest, JobsEndingWhileTheDatabaseIsDownForLessThanALeaseEndOnce) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(3));
  const v1::TMesh mesh = MeshTakingSeconds(1.5);
  for (int i = 0; i < 3; ++i) SubmitAndFollow(i, RequestFor(mesh, 100));
  for (int i = 0; i < 9; ++i) SubmitAndFollow(i % 3, RequestFor(NotchMesh(), kLevels[i % 8]));
  // A call-bound job too: its call gets its result, its record follows.
  std::optional<client::JobOutcome> call;
  absl::Notification call_accepted;
  std::thread calling([&] {
    client::QuantizerClient client = Client(2);
    call = client.Quantize(RequestFor(mesh, 50),
                           StreamFor(kJobTimeout, [&](const v1::QuantizeEvent& event) {
                             if (event.has_accepted()) call_accepted.Notify();
                             return true;
                           }));
  });
  ASSERT_TRUE(call_accepted.WaitForNotificationWithTimeout(absl::Seconds(120)));
  // Stop the database as soon as every replica runs a job, so that they end during the outage.
  for (const absl::Time until = absl::Now() + absl::Seconds(120); absl::Now() < until;) {
    int running = 0;
    for (const auto& replica : replicas_) {
      running += replica->Log().find("event=job_start") != std::string::npos;
    }
    if (running == 3) break;
    absl::SleepFor(absl::Milliseconds(20));
  }
  ASSERT_TRUE(postgres_->Stop().ok());
  absl::SleepFor(absl::Seconds(kLeaseSeconds * 2 / 3));  // shorter than the lease
  ASSERT_TRUE(postgres_->Restart().ok());
  calling.join();
  ASSERT_TRUE(call.has_value());
  EXPECT_TRUE(call->status.ok()) << call->status;
  ASSERT_TRUE(call->result.has_value());
  EXPECT_EQ(absl::StrJoin(call->result->q(), ","),
            absl::StrJoin(LocalQ(RequestFor(mesh, 50)), ","));
  Acknowledged(call->job, RequestFor(mesh, 50));
  ExpectEveryJobEndedOnceWithTheLocalQ();
  int retried = 0;
  for (const auto& replica : replicas_) {
    retried += replica->Log().find("event=job_record_failed") != std::string::npos;
  }
  std::cout << "replicas whose records waited for the database: " << retried << " of 3\n";
}

// While the database is down: liveness always SERVING, readiness NOT_SERVING, few log lines and
// no CPU spent spinning; afterwards readiness comes back and jobs run.
TEST_F(StoreFaultsTest, AnOutageCostsNeitherLogsNorCpuAndOnlyReadinessSaysSo) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(3));
  Prober prober(Channels(), absl::Milliseconds(500));
  absl::SleepFor(absl::Seconds(2));
  for (const ProbeCounts& ready : prober.readiness()) {
    EXPECT_GT(ready.serving, 0) << "ready before the outage";
  }
  const std::vector<std::string> logs_before = LogSnapshots();
  std::vector<double> cpu_before;
  for (const auto& replica : replicas_) cpu_before.push_back(CpuSeconds(replica->pid()));
  ASSERT_TRUE(postgres_->Stop().ok());
  const absl::Time outage_start = absl::Now();
  // Readiness turns NOT_SERVING within two of the manifests' probe periods (5 s each).
  absl::SleepFor(absl::Seconds(10));
  prober.Reset();
  absl::SleepFor(absl::Seconds(10));
  const std::vector<ProbeCounts> liveness = prober.liveness();
  const std::vector<ProbeCounts> readiness = prober.readiness();
  const double outage_seconds = absl::ToDoubleSeconds(absl::Now() - outage_start);
  const std::vector<std::string> logs_after = LogSnapshots();
  for (size_t i = 0; i < replicas_.size(); ++i) {
    const double cpu = CpuSeconds(replicas_[i]->pid()) - cpu_before[i];
    const int64_t lines = LineCount(logs_after[i]) - LineCount(logs_before[i]);
    std::cout << "replica " << i << " during a " << outage_seconds << " s outage: " << lines
              << " log lines (" << lines / outage_seconds << "/s), " << cpu << " s CPU; liveness "
              << liveness[i].Describe() << "; readiness (after 10 s) " << readiness[i].Describe()
              << "\n";
    EXPECT_LE(lines / outage_seconds, 10) << logs_after[i].substr(logs_before[i].size());
    EXPECT_LT(cpu / outage_seconds, 0.2) << "a loop spins";
    EXPECT_EQ(liveness[i].failed + liveness[i].not_serving, 0) << "liveness " << i;
    EXPECT_GT(liveness[i].serving, 0);
    EXPECT_EQ(readiness[i].serving + readiness[i].failed, 0) << "readiness " << i;
    EXPECT_GT(readiness[i].not_serving, 0);
  }
  ASSERT_TRUE(postgres_->Restart().ok());
  // Ready again, and jobs run.
  for (size_t i = 0; i < replicas_.size(); ++i) {
    bool ready = false;
    client::QuantizerClient client = Client(i);
    for (const absl::Time until = absl::Now() + absl::Seconds(60); !ready && absl::Now() < until;) {
      const auto status = client::CheckHealth(client.channel(), "readiness", kProbeTimeout);
      ready = status.ok() && *status == client::ServingStatus::kServing;
      if (!ready) absl::SleepFor(absl::Milliseconds(100));
    }
    EXPECT_TRUE(ready) << "replica " << i << " ready again";
    SubmitAndFollow(i, RequestFor(NotchMesh(), 100));
  }
  prober.Stop();
  ExpectEveryJobEndedOnceWithTheLocalQ();
}

// The database hangs (SIGSTOP) while jobs run and clients keep asking about them: liveness
// answers every probe, calls fail with UNAVAILABLE instead of hanging, and once the database
// runs again every job ends once.
TEST_F(StoreFaultsTest, AFrozenDatabaseNeverStopsLivenessAndJobsEndOnceAfterwards) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(3));
  const v1::TMesh mesh = MeshTakingSeconds(2);
  std::vector<std::string> jobs;
  for (int i = 0; i < 3; ++i) jobs.push_back(SubmitAndFollow(i, RequestFor(mesh, 100)));
  for (int i = 0; i < 6; ++i) jobs.push_back(SubmitAndFollow(i % 3, RequestFor(NotchMesh(), 100)));
  Prober prober(Channels(), absl::Milliseconds(500));
  // Clients polling their jobs as a UI would, 8 per replica, without the client library's
  // retries on UNAVAILABLE, so that what one call of the server does shows.
  std::atomic<bool> stop_polling = false;
  std::atomic<int> polls_ok = 0;
  std::atomic<int> polls_unavailable = 0;
  std::atomic<int> polls_other = 0;
  std::atomic<int64_t> slowest_poll_ms = 0;
  std::vector<std::thread> pollers;
  for (int p = 0; p < 24; ++p) {
    pollers.emplace_back([&, p] {
      grpc::ChannelArguments arguments;
      arguments.SetInt(GRPC_ARG_ENABLE_RETRIES, 0);
      client::QuantizerClient client(grpc::CreateCustomChannel(
          replicas_[p % 3]->address(), grpc::InsecureChannelCredentials(), arguments));
      while (!stop_polling) {
        const absl::Time start = absl::Now();
        const absl::StatusOr<v1::Job> got = client.GetJob(jobs[p % jobs.size()]);
        const int64_t ms = absl::ToInt64Milliseconds(absl::Now() - start);
        for (int64_t seen = slowest_poll_ms;
             ms > seen && !slowest_poll_ms.compare_exchange_weak(seen, ms);) {
        }
        if (got.ok()) {
          ++polls_ok;
        } else if (absl::IsUnavailable(got.status())) {
          ++polls_unavailable;
        } else {
          ++polls_other;
        }
        absl::SleepFor(absl::Milliseconds(50));
      }
    });
  }
  absl::SleepFor(absl::Seconds(1));
  prober.Reset();
  ASSERT_TRUE(postgres_->Freeze().ok());
  absl::SleepFor(absl::Seconds(10));
  const std::vector<ProbeCounts> liveness = prober.liveness();
  const std::vector<ProbeCounts> readiness = prober.readiness();
  ASSERT_TRUE(postgres_->Thaw().ok());
  stop_polling = true;
  for (std::thread& poller : pollers) poller.join();
  prober.Stop();
  std::cout << "GetJob during and around a 10 s freeze: " << polls_ok << " answered, "
            << polls_unavailable << " UNAVAILABLE, " << polls_other << " other; the slowest took "
            << slowest_poll_ms << " ms (store timeout " << kStoreTimeoutSeconds << " s)\n";
  EXPECT_EQ(polls_other, 0);
  EXPECT_GT(polls_unavailable, 0) << "calls during the freeze fail instead of waiting it out";
  for (size_t i = 0; i < replicas_.size(); ++i) {
    std::cout << "replica " << i << " during the freeze: liveness " << liveness[i].Describe()
              << "; readiness " << readiness[i].Describe() << "\n";
    EXPECT_EQ(liveness[i].failed + liveness[i].not_serving, 0) << "liveness " << i;
    EXPECT_GT(readiness[i].not_serving, 0) << "readiness " << i;
  }
  ExpectEveryJobEndedOnceWithTheLocalQ();
}

// The second row of the issue: replica A is frozen past its lease while it runs a job; B claims
// the job and is drained (SIGTERM gives the job back); A resumes. A must write nothing over the
// job: it ends once, SUCCEEDED and converged, and every stream gets its terminal event.
TEST_F(StoreFaultsTest, AFrozenReplicaThatResumesAfterATakeOverAndAHandBackWritesNothing) {
  constexpr double kShortLease = 2;
  ASSERT_NO_FATAL_FAILURE(StartReplica(0, kShortLease));
  const v1::QuantizeRequest request = RequestFor(MeshTakingSeconds(6), 100);
  const std::string job = SubmitAndFollow(0, request);
  ASSERT_FALSE(job.empty());
  ASSERT_TRUE(replicas_[0]->WaitForLog(absl::StrCat("event=job_start job=", job)));
  // A short grace: a drained replica interrupts its runs after a quarter of it.
  ASSERT_NO_FATAL_FAILURE(StartReplica(1, kShortLease, /*grace_seconds=*/1));
  ASSERT_NO_FATAL_FAILURE(StartReplica(2, kShortLease, /*grace_seconds=*/1));
  Follow(job, 2);  // a second follower, through the replica that neither runs nor drains
  replicas_[0]->Signal(SIGSTOP);
  // B (1 or 2) claims it once A's lease has expired.
  const std::string claimed_again = absl::StrCat("event=job_claimed job=", job, " attempt=2");
  size_t taker = 0;
  for (const absl::Time until = absl::Now() + absl::Seconds(120); taker == 0;) {
    if (replicas_[1]->Log().find(claimed_again) != std::string::npos) taker = 1;
    if (replicas_[2]->Log().find(claimed_again) != std::string::npos) taker = 2;
    ASSERT_LT(absl::Now(), until) << "nobody claimed the frozen replica's job";
    absl::SleepFor(absl::Milliseconds(20));
  }
  // B is drained before it ends the run: the job goes back to the queue.
  replicas_[taker]->Signal(SIGTERM);
  ASSERT_TRUE(replicas_[taker]->WaitForExit(absl::Seconds(60)).has_value());
  EXPECT_NE(replicas_[taker]->Log().find(absl::StrCat("event=job_released job=", job)),
            std::string::npos)
      << "the drained replica gave the job back";
  replicas_[0]->Signal(SIGCONT);
  ExpectEveryJobEndedOnceWithTheLocalQ();
  EXPECT_NE(replicas_[0]->Log().find(absl::StrCat("event=job_lease_lost job=", job)),
            std::string::npos)
      << "the resumed replica learned it lost the job";
}

// kill -9 of replicas during bursts of submissions: every submission a client saw acknowledged
// (retried with its request_id until it was) ends once; nothing else is in the store.
TEST_F(StoreFaultsTest, KillingReplicasDuringSubmitBurstsLosesAndDuplicatesNothing) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(3));
  constexpr int kClients = 4;
  constexpr int kJobsPerClient = 30;
  std::atomic<int> submitted = 0;
  std::vector<std::thread> clients;
  for (int c = 0; c < kClients; ++c) {
    clients.emplace_back([&, c] {
      for (int j = 0; j < kJobsPerClient; ++j) {
        v1::QuantizeRequest request = RequestFor(NotchMesh(), kLevels[(c + j) % 8]);
        request.set_request_id(absl::StrCat("client", c, "-job", j));
        // Retried through the next replica until acknowledged, as a careful client does.
        for (int attempt = 0;; ++attempt) {
          std::optional<client::QuantizerClient> client;
          {
            std::lock_guard<std::mutex> lock(mutex_);
            const size_t index = (c + j + attempt) % replicas_.size();
            client = ClientOf(*replicas_[index]);
          }
          if (client.has_value()) {
            const absl::StatusOr<v1::Job> job = client->SubmitJob(request);
            if (job.ok()) {
              v1::QuantizeRequest plain = request;
              plain.clear_request_id();
              Acknowledged(job->name(), plain);
              ++submitted;
              break;
            }
          }
          ASSERT_LT(attempt, 1000) << "never acknowledged";
          absl::SleepFor(absl::Milliseconds(50));
        }
      }
    });
  }
  for (int kill = 0; kill < 2; ++kill) {
    for (const absl::Time until = absl::Now() + absl::Seconds(120);
         submitted < (kill + 1) * kClients * kJobsPerClient / 3 && absl::Now() < until;) {
      absl::SleepFor(absl::Milliseconds(10));
    }
    replicas_[kill]->Signal(SIGKILL);
    ASSERT_TRUE(replicas_[kill]->WaitForExit(absl::Seconds(10)).has_value());
    std::unique_ptr<ServerProcess> restarted = StartServerOrFail(ReplicaFlags(kLeaseSeconds));
    ASSERT_NE(restarted, nullptr);
    std::lock_guard<std::mutex> lock(mutex_);
    replicas_[kill] = std::move(restarted);
  }
  for (std::thread& client : clients) client.join();
  EXPECT_EQ(submitted, kClients * kJobsPerClient);
  ExpectEveryJobEndedOnceWithTheLocalQ();
}

}  // namespace
}  // namespace ispq::testing
