// SPDX-License-Identifier: Apache-2.0
// Several ispq-server replicas sharing one PostgreSQL job store (--job_store=postgresql://...),
// on loopback: a real PostgreSQL started by the test (tests/support/postgres_instance.h) and
// three real server processes. Jobs submitted to one replica are watched, fetched and cancelled
// through the others; a replica killed with SIGKILL while running jobs loses none of them (its
// lease expires and another replica runs them again); restarting every replica keeps every job;
// a client with round_robin spreads its calls over the replicas.
#include <signal.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/synchronization/notification.h"
#include "absl/time/clock.h"
#include "gtest/gtest.h"
#include "tests/integration/server_process.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/postgres_instance.h"
#include "tests/support/postgres_suite.h"

namespace ispq::testing {
namespace {

// Short, so that a killed replica's jobs are run again quickly; renewed every third of it.
constexpr double kLeaseSeconds = 1.5;

class ReplicasTest : public PostgresSuite {
 protected:
  void SetUp() override {
    absl::StatusOr<std::string> uri =
        postgres_->CreateDatabase(absl::StrCat("replicas", next_database_++));
    ASSERT_TRUE(uri.ok()) << uri.status();
    uri_ = *uri;
  }

  std::vector<std::string> ReplicaFlags(int workers = 1) const {
    return {absl::StrCat("--job_store=", uri_), absl::StrCat("--workers=", workers),
            absl::StrCat("--job_lease_seconds=", kLeaseSeconds), "--shutdown_grace_seconds=4",
            "--max_queued_jobs=1000"};
  }

  // Starts replica `index` (replacing a dead one).
  void StartReplica(size_t index, int workers = 1) {
    if (replicas_.size() <= index) replicas_.resize(index + 1);
    replicas_[index] = StartServerOrFail(ReplicaFlags(workers));
    ASSERT_NE(replicas_[index], nullptr);
  }
  void StartReplicas(int count, int workers = 1) {
    for (int i = 0; i < count; ++i) ASSERT_NO_FATAL_FAILURE(StartReplica(i, workers));
  }
  client::QuantizerClient Client(size_t index) { return ClientOf(*replicas_[index]); }

  // Every result a replica gives for `job` is the same valid one.
  void ExpectSameValidResultEverywhere(const std::string& job, const v1::TMesh& mesh) {
    std::optional<v1::QuantizationResult> first;
    for (size_t i = 0; i < replicas_.size(); ++i) {
      client::QuantizerClient client = Client(i);
      const absl::StatusOr<v1::Job> got = client.GetJob(job);
      ASSERT_TRUE(got.ok()) << "replica " << i << ": " << got.status();
      ASSERT_EQ(got->state(), v1::SUCCEEDED) << job << " on replica " << i;
      ASSERT_TRUE(IsValidResult(mesh, got->result())) << job;
      if (!first.has_value()) first = got->result();
      EXPECT_EQ(absl::StrJoin(got->result().q(), ","), absl::StrJoin(first->q(), ","));
    }
  }

  std::string uri_;
  std::vector<std::unique_ptr<ServerProcess>> replicas_;
};

TEST_F(ReplicasTest, AJobSubmittedToOneReplicaIsWatchedFetchedAndCancelledThroughTheOthers) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(3));
  client::QuantizerClient submitter = Client(0);
  client::QuantizerClient watcher = Client(1);
  client::QuantizerClient other = Client(2);

  const absl::StatusOr<v1::Job> job = submitter.SubmitJob(RequestFor(NotchMesh(), 100));
  ASSERT_TRUE(job.ok()) << job.status();
  int events = 0;
  const client::JobOutcome outcome =
      watcher.FollowJob(job->name(), 0, StreamFor(kJobTimeout, [&events](const v1::QuantizeEvent&) {
                          ++events;
                          return true;
                        }));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  ASSERT_TRUE(outcome.result.has_value());
  EXPECT_TRUE(IsValidResult(NotchMesh(), *outcome.result));
  EXPECT_GE(events, 2) << "at least the accepted event and the result";
  ExpectSameValidResultEverywhere(job->name(), NotchMesh());

  v1::ListJobsRequest list;
  const absl::StatusOr<v1::ListJobsResponse> listed = other.ListJobs(list);
  ASSERT_TRUE(listed.ok()) << listed.status();
  ASSERT_EQ(listed->jobs_size(), 1);
  EXPECT_EQ(listed->jobs(0).name(), job->name());

  // A mesh stored through one replica is usable through another.
  const absl::StatusOr<v1::Mesh> stored = watcher.CreateMesh(NotchMesh());
  ASSERT_TRUE(stored.ok()) << stored.status();
  const absl::StatusOr<v1::Job> on_stored = other.SubmitJob(StoredMeshRequest(stored->name(), 50));
  ASSERT_TRUE(on_stored.ok()) << on_stored.status();
  const absl::StatusOr<v1::Job> stored_done = WaitUntilDone(submitter, on_stored->name());
  ASSERT_TRUE(stored_done.ok()) << stored_done.status();
  EXPECT_TRUE(IsValidResult(NotchMesh(), stored_done->result()));
  ASSERT_TRUE(submitter.GetMesh(stored->name()).ok());

  // Cancelled through a third replica while it runs on whichever claimed it.
  const absl::StatusOr<v1::Job> long_job = submitter.SubmitJob(RequestFor(LongRunningMesh(), 100));
  ASSERT_TRUE(long_job.ok()) << long_job.status();
  ASSERT_TRUE(WaitForState(watcher, long_job->name(), v1::RUNNING).ok());
  ASSERT_TRUE(other.CancelJob(long_job->name()).ok());
  // Ended by the cancel, not by its end: CANCELLED, however long the cancel took to arrive.
  const absl::StatusOr<v1::Job> cancelled = WaitUntilDone(submitter, long_job->name());
  ASSERT_TRUE(cancelled.ok()) << cancelled.status() << "\n"
                              << replicas_[0]->Log() << replicas_[1]->Log() << replicas_[2]->Log();
  EXPECT_EQ(cancelled->state(), v1::CANCELLED)
      << replicas_[0]->Log() << replicas_[1]->Log() << replicas_[2]->Log();

  // An unknown job is NOT_FOUND on every replica.
  EXPECT_EQ(other.GetJob("jobs/never-submitted").status().code(), absl::StatusCode::kNotFound);
}

TEST_F(ReplicasTest, AKilledReplicasJobsAreRunAgainElsewhereAndNothingIsLost) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(3));
  // 300 jobs submitted round robin: every 25th takes about a second, so that every replica is
  // busy when one is killed; the others are small.
  const v1::TMesh mesh = MeshTakingSeconds(1.0);
  constexpr int kLevels[] = {0, 1, 5, 10, 17, 25, 50, 100};
  std::vector<client::QuantizerClient> clients;
  for (size_t i = 0; i < 3; ++i) clients.push_back(Client(i));
  std::vector<std::string> jobs;
  std::vector<std::string> long_jobs;
  std::map<std::string, const v1::TMesh*> mesh_of;
  for (int i = 0; i < 300; ++i) {
    const bool long_job = i % 25 == 0;
    const v1::TMesh& used = long_job ? mesh : NotchMesh();
    const absl::StatusOr<v1::Job> job =
        clients[i % 3].SubmitJob(RequestFor(used, long_job ? 100 : kLevels[i % 8]));
    ASSERT_TRUE(job.ok()) << job.status();
    jobs.push_back(job->name());
    if (long_job) long_jobs.push_back(job->name());
    mesh_of[job->name()] = &used;
  }
  // Kill a replica while it runs a long job (whichever replica claims one), once a watcher
  // follows the job through it; the watcher loses the stream. Ordered by what the logs and the
  // stream say, not by sleeps: on a loaded machine any step may take a while.
  // A long job replica `replica` runs now, or "" (its log is read once: it grows long).
  auto running_long_job = [&](size_t replica) -> std::string {
    const std::string log = replicas_[replica]->Log();
    for (const std::string& job : long_jobs) {
      if (log.find(absl::StrCat("event=job_start job=", job)) != std::string::npos &&
          log.find(absl::StrCat("event=job_end job=", job)) == std::string::npos) {
        return job;
      }
    }
    return "";
  };
  size_t victim = 0;
  std::string victim_job;
  client::JobOutcome broken;
  absl::Time killed;
  while (victim_job.empty()) {
    std::string running;
    ASSERT_TRUE(WaitUntil(
        [&] {
          for (victim = 0; victim < 3; ++victim) {
            if (!(running = running_long_job(victim)).empty()) return true;
          }
          return false;
        },
        kJobTimeout, absl::Milliseconds(20)))
        << "no replica was seen running a long job";
    absl::Notification streaming;
    std::thread watching([&] {
      broken = clients[victim].WatchJob(running, 0,
                                        StreamFor(kJobTimeout, [&](const v1::QuantizeEvent&) {
                                          if (!streaming.HasBeenNotified()) streaming.Notify();
                                          return true;
                                        }));
      if (!streaming.HasBeenNotified()) streaming.Notify();  // it failed before any event
    });
    streaming.WaitForNotification();
    // The job may have ended meanwhile (then the stream ends with it): look for another one.
    if (running_long_job(victim) == running) {
      replicas_[victim]->Signal(SIGKILL);
      killed = absl::Now();
      victim_job = running;
    }
    watching.join();
  }
  ASSERT_TRUE(replicas_[victim]->WaitForExit(kSafetyNet).has_value());
  EXPECT_FALSE(broken.job_ended);

  // The watcher resumes through another replica and gets the result of the second run.
  const size_t survivor = (victim + 1) % 3;
  const client::JobOutcome resumed =
      clients[survivor].FollowJob(victim_job, broken.next_event, StreamFor(kJobTimeout));
  ASSERT_TRUE(resumed.status.ok()) << resumed.status;
  ASSERT_TRUE(resumed.result.has_value());
  EXPECT_TRUE(IsValidResult(mesh, *resumed.result));
  const absl::Duration rerun = absl::Now() - killed;
  bool claimed_again = false;
  for (size_t i = 0; i < 3; ++i) {
    claimed_again |=
        i != victim && replicas_[i]->Log().find(absl::StrCat("event=job_claimed job=", victim_job,
                                                             " attempt=2")) != std::string::npos;
  }
  EXPECT_TRUE(claimed_again) << "the killed replica's job was run again by another";
  std::cout << "killed replica's job " << victim_job << " ended through another replica "
            << absl::ToDoubleSeconds(rerun) << " s after the kill (lease " << kLeaseSeconds
            << " s)\n";

  ASSERT_NO_FATAL_FAILURE(StartReplica(victim));  // back, as a Deployment would bring it
  for (const std::string& job : jobs) {
    const absl::StatusOr<v1::Job> done = WaitUntilDone(clients[survivor], job);
    ASSERT_TRUE(done.ok()) << done.status();
    ASSERT_NO_FATAL_FAILURE(ExpectSameValidResultEverywhere(job, *mesh_of[job]));
    ASSERT_TRUE(IsValidResult(*mesh_of[job], done->result())) << job;
  }
  // Exactly the submitted jobs exist: no duplicates, none lost.
  v1::ListJobsRequest list;
  list.set_page_size(1000);
  const absl::StatusOr<v1::ListJobsResponse> listed = Client(0).ListJobs(list);
  ASSERT_TRUE(listed.ok()) << listed.status();
  std::set<std::string> names;
  for (const v1::Job& job : listed->jobs()) names.insert(job.name());
  EXPECT_EQ(names, std::set<std::string>(jobs.begin(), jobs.end()));
  EXPECT_EQ(names.size(), 300u);
}

// Not a pass/fail bound (2 cores cannot run 3 workers at once): measures and prints what the
// closing note of issue 10 reports, and checks every result.
TEST_F(ReplicasTest, MeasuresSubmitLatencyAndThroughputOfOneAndThreeReplicas) {
  const v1::TMesh& mesh = NotchMesh();  // small jobs: what the replicas add shows
  double one = 0;                       // jobs per second with one replica
  double three = 0;                     // and with three
  auto run = [&](int replicas) {
    for (auto& replica : replicas_) replica.reset();
    replicas_.clear();
    SetUp();  // a fresh database
    StartReplicas(replicas);
    std::vector<client::QuantizerClient> clients;
    for (int i = 0; i < replicas; ++i) clients.push_back(Client(i));
    const absl::Time start = absl::Now();
    std::vector<std::string> jobs;
    double* const jobs_per_second = replicas == 1 ? &one : &three;
    for (int i = 0; i < 120; ++i) {
      const absl::StatusOr<v1::Job> job = clients[i % replicas].SubmitJob(RequestFor(mesh, 100));
      EXPECT_TRUE(job.ok()) << job.status();
      if (job.ok()) jobs.push_back(job->name());
    }
    for (const std::string& job : jobs) {
      const absl::StatusOr<v1::Job> done = WaitUntilDone(clients[0], job);
      ASSERT_TRUE(done.ok()) << done.status();
      EXPECT_TRUE(IsValidResult(mesh, done->result())) << job << " " << done->DebugString();
    }
    if (std::getenv("ISPQ_DUMP_LOG")) {
      std::ofstream(absl::StrCat("/tmp/measure", replicas, ".log")) << replicas_[0]->Log();
    }
    *jobs_per_second = jobs.size() / absl::ToDoubleSeconds(absl::Now() - start);
  };
  ASSERT_NO_FATAL_FAILURE(run(1));
  ASSERT_NO_FATAL_FAILURE(run(3));
  std::cout << "throughput, 120 notch jobs (~25 ms solves), 1 worker per replica: 1 replica " << one
            << " jobs/s, 3 replicas " << three << " jobs/s (" << 100 * three / (3 * one)
            << " % of 3x one)\n";

  auto median_submit_ms = [&](const std::vector<std::string>& flags) {
    std::unique_ptr<ServerProcess> server = StartServerOrFail(flags);
    client::QuantizerClient client = ClientOf(*server);
    std::vector<double> latencies;
    for (int i = 0; i < 40; ++i) {
      const absl::Time start = absl::Now();
      EXPECT_TRUE(client.SubmitJob(RequestFor(NotchMesh(), 0)).ok());
      latencies.push_back(absl::ToDoubleMilliseconds(absl::Now() - start));
    }
    std::sort(latencies.begin(), latencies.end());
    return latencies[latencies.size() / 2];
  };
  const double memory_ms = median_submit_ms({"--workers=1"});
  const double postgres_ms = median_submit_ms(ReplicaFlags());
  std::cout << "SubmitJob median latency (notch mesh): in-memory " << memory_ms
            << " ms, PostgreSQL " << postgres_ms << " ms\n";
}

TEST_F(ReplicasTest, RestartingEveryReplicaKeepsEveryJob) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(3));
  constexpr int kLevels[] = {0, 1, 5, 10, 17, 25, 50, 100};
  std::vector<std::string> jobs;
  for (int i = 0; i < 30; ++i) {
    client::QuantizerClient client = Client(i % 3);
    const absl::StatusOr<v1::Job> job = client.SubmitJob(RequestFor(NotchMesh(), kLevels[i % 8]));
    ASSERT_TRUE(job.ok()) << job.status();
    jobs.push_back(job->name());
  }
  // A rolling restart right away: whatever is queued or running goes on in the new replicas.
  for (size_t i = 0; i < 3; ++i) {
    replicas_[i]->Signal(SIGTERM);
    ASSERT_EQ(replicas_[i]->WaitForExit(kSafetyNet), std::optional<int>(0));
    ASSERT_NO_FATAL_FAILURE(StartReplica(i));
  }
  client::QuantizerClient client = Client(1);
  for (const std::string& job : jobs) {
    const absl::StatusOr<v1::Job> done = WaitUntilDone(client, job);
    ASSERT_TRUE(done.ok()) << done.status();
    ASSERT_EQ(done->state(), v1::SUCCEEDED) << job;
    EXPECT_TRUE(IsValidResult(NotchMesh(), done->result()));
  }
}

// An uploaded mesh (UploadMesh: decoded from its chunks, never parsed as one message) is kept in
// the shared store as its binary protobuf: another replica, which never saw the upload, decodes
// it from there and runs a job on it by name, with the q a job on the inline mesh gets.
TEST_F(ReplicasTest, AMeshUploadedToOneReplicaIsQuantizedByAnother) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(2));
  const v1::TMesh mesh = FemurCopies(3);
  client::QuantizerClient uploader = Client(0);
  const absl::StatusOr<v1::Mesh> stored = uploader.UploadMesh(mesh, /*chunk_bytes=*/4096);
  ASSERT_TRUE(stored.ok()) << stored.status();
  EXPECT_EQ(stored->mesh_stats().arcs(), mesh.arcs_size());
  client::QuantizerClient other = Client(1);
  const client::JobOutcome by_name =
      other.Quantize(StoredMeshRequest(stored->name(), 25), StreamFor(kJobTimeout));
  ASSERT_TRUE(by_name.status.ok()) << by_name.status;
  ASSERT_TRUE(IsValidResult(mesh, *by_name.result));
  const client::JobOutcome inline_mesh =
      other.Quantize(RequestFor(mesh, 25), StreamFor(kJobTimeout));
  ASSERT_TRUE(inline_mesh.status.ok()) << inline_mesh.status;
  EXPECT_EQ(absl::StrJoin(by_name.result->q(), ","), absl::StrJoin(inline_mesh.result->q(), ","));
}

TEST_F(ReplicasTest, RoundRobinSpreadsCallsOverEveryReplica) {
  ASSERT_NO_FATAL_FAILURE(StartReplicas(3));
  client::ServerConnection connection;
  connection.address = absl::StrCat(replicas_[0]->address(), ",", replicas_[1]->address(), ",",
                                    replicas_[2]->address());
  connection.lb_policy = "round_robin";
  absl::StatusOr<client::QuantizerClient> balanced = client::QuantizerClient::Connect(connection);
  ASSERT_TRUE(balanced.ok()) << balanced.status();
  auto accepted_per_replica = [&] {
    std::vector<int64_t> accepted;
    for (size_t i = 0; i < 3; ++i) {
      const absl::StatusOr<v1::ServerStats> stats = Client(i).GetServerStats();
      EXPECT_TRUE(stats.ok()) << stats.status();
      accepted.push_back(stats.ok() ? stats->accepted_total() : 0);
    }
    return accepted;
  };
  // The policy has connected to every address first, as a long-lived client's would have: once
  // every replica has accepted a job through it (round_robin picks only connected replicas, so
  // until then the spread would measure how soon connections came up, which a sleep guessed).
  std::vector<int64_t> before;
  ASSERT_TRUE(WaitUntil(
      [&] {
        const absl::StatusOr<v1::Job> job = balanced->SubmitJob(RequestFor(NotchMesh(), 10));
        EXPECT_TRUE(job.ok()) << job.status();
        before = accepted_per_replica();
        return std::ranges::all_of(before, [](int64_t count) { return count > 0; });
      },
      kSafetyNet, absl::Milliseconds(20)))
      << "a replica never got a job: " << absl::StrJoin(before, ", ");
  constexpr int kJobs = 30;
  for (int i = 0; i < kJobs; ++i) {
    const absl::StatusOr<v1::Job> job = balanced->SubmitJob(RequestFor(NotchMesh(), 10));
    ASSERT_TRUE(job.ok()) << job.status();
  }
  const std::vector<int64_t> after = accepted_per_replica();
  std::vector<int64_t> accepted;
  for (size_t i = 0; i < 3; ++i) accepted.push_back(after[i] - before[i]);
  std::cout << "round_robin: accepted per replica " << absl::StrJoin(accepted, ", ") << "\n";
  for (int64_t count : accepted) EXPECT_GE(count, kJobs / 3 - 2);

  connection.lb_policy = "no_such_policy";
  EXPECT_EQ(client::QuantizerClient::Connect(connection).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace ispq::testing
