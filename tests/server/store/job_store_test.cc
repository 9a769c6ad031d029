// SPDX-License-Identifier: Apache-2.0
#include "server/store/job_store.h"

#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gtest/gtest.h"
#include "server/store/in_memory_job_store.h"
#include "server/store/postgres/postgres_job_store.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/postgres_instance.h"

namespace ispq::server {
namespace {

const absl::Time kT0 = absl::FromUnixSeconds(1'000'000);

// A job this replica runs (call-bound): a shared store records its changes as it makes them.
// (A job queued for any replica is recorded by the replica that claims it, see
// postgres_job_claims_test.cc.)
std::shared_ptr<Job> JobRunHere(const std::string& id, absl::Time now) {
  return std::make_shared<Job>(id, NotchJobSpec(), /*bound_to_call=*/true, /*queue_position=*/0,
                               now);
}

// Ends `job` and waits until `store` has recorded it.
void Finish(JobStore& store, Job& job, absl::Time when) {
  job.FinishWithError(absl::InternalError("done for the test"), when);
  ASSERT_TRUE(store.Flush(absl::Now() + absl::Seconds(30)));
}

// Every test runs against both implementations of the interface: the in-memory store and the
// PostgreSQL store on a real PostgreSQL (one server for the suite, a fresh database per test).
class JobStoreTest : public ::testing::TestWithParam<std::string> {
 protected:
  static void SetUpTestSuite() {
    absl::StatusOr<std::unique_ptr<ispq::testing::PostgresInstance>> started =
        ispq::testing::PostgresInstance::Start();
    ASSERT_TRUE(started.ok()) << started.status();
    postgres_ = started->release();
  }
  static void TearDownTestSuite() {
    delete postgres_;
    postgres_ = nullptr;
  }

  std::unique_ptr<JobStore> NewStore(RetentionPolicy policy) {
    if (GetParam() == "memory") return std::make_unique<InMemoryJobStore>(policy);
    absl::StatusOr<std::string> uri =
        postgres_->CreateDatabase(absl::StrCat("store", next_database_++));
    EXPECT_TRUE(uri.ok()) << uri.status();
    PostgresJobStoreOptions options;
    options.uri = *uri;
    options.retention = policy;
    options.lease = absl::Seconds(5);
    absl::StatusOr<std::unique_ptr<PostgresJobStore>> store = PostgresJobStore::Open(options);
    EXPECT_TRUE(store.ok()) << store.status();
    return *std::move(store);
  }

  static std::shared_ptr<Job> Add(JobStore& store, std::shared_ptr<Job> job, absl::Time now) {
    absl::StatusOr<std::shared_ptr<Job>> added = store.Add(job, "", now);
    EXPECT_TRUE(added.ok()) << added.status();
    return job;
  }

  static ispq::testing::PostgresInstance* postgres_;
  static int next_database_;
};

ispq::testing::PostgresInstance* JobStoreTest::postgres_ = nullptr;
int JobStoreTest::next_database_ = 0;

INSTANTIATE_TEST_SUITE_P(BothStores, JobStoreTest, ::testing::Values("memory", "postgresql"),
                         [](const auto& info) { return info.param; });

TEST_P(JobStoreTest, KeepsActiveJobsAndTheNewestFinishedOnes) {
  std::unique_ptr<JobStore> owned = NewStore({.max_finished = 2, .max_age = absl::Hours(1)});
  JobStore& store = *owned;
  std::vector<std::shared_ptr<Job>> jobs;
  for (int i = 0; i < 4; ++i) {
    jobs.push_back(JobRunHere(absl::StrCat("job", i), kT0));
    Add(store, jobs.back(), kT0);
  }
  Finish(store, *jobs[0], kT0 + absl::Seconds(1));
  Finish(store, *jobs[1], kT0 + absl::Seconds(2));
  Finish(store, *jobs[2], kT0 + absl::Seconds(3));
  const absl::Time now = kT0 + absl::Seconds(4);
  EXPECT_EQ(store.Find("job0", now), nullptr);  // the oldest finished beyond the count
  EXPECT_NE(store.Find("job1", now), nullptr);
  EXPECT_NE(store.Find("job2", now), nullptr);
  EXPECT_NE(store.Find("job3", now), nullptr);  // running jobs are never evicted
  EXPECT_EQ(store.ActiveJobs().size(), 1u);
}

TEST_P(JobStoreTest, ForgetsFinishedJobsAfterTheRetentionTime) {
  std::unique_ptr<JobStore> owned = NewStore({.max_finished = 100, .max_age = absl::Minutes(10)});
  JobStore& store = *owned;
  std::shared_ptr<Job> job = JobRunHere("old", kT0);
  Add(store, job, kT0);
  Finish(store, *job, kT0);
  EXPECT_NE(store.Find("old", kT0 + absl::Minutes(10)), nullptr);
  EXPECT_EQ(store.Find("old", kT0 + absl::Minutes(10) + absl::Seconds(1)), nullptr);
}

JobStore::Query Page(int size, const std::string& token,
                     v1::JobState state = v1::JOB_STATE_UNSPECIFIED) {
  JobStore::Query query;
  query.page_size = size;
  query.page_token = token;
  query.state = state;
  return query;
}

TEST_P(JobStoreTest, ListsNewestFirstInPagesAndByState) {
  std::unique_ptr<JobStore> owned = NewStore({});
  JobStore& store = *owned;
  std::vector<std::shared_ptr<Job>> jobs;
  for (int i = 0; i < 5; ++i)
    jobs.push_back(Add(store, JobRunHere(absl::StrCat("j", i), kT0), kT0));
  Finish(store, *jobs[1], kT0);
  absl::StatusOr<JobStore::Page> first = store.List(Page(2, ""), kT0);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(first->jobs.size(), 2u);
  EXPECT_EQ(first->jobs[0].job->id(), "j4");
  EXPECT_EQ(first->jobs[1].job->id(), "j3");
  absl::StatusOr<JobStore::Page> second = store.List(Page(2, first->next_page_token), kT0);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second->jobs[0].job->id(), "j2");
  EXPECT_EQ(second->jobs[1].job->id(), "j1");
  absl::StatusOr<JobStore::Page> third = store.List(Page(2, second->next_page_token), kT0);
  ASSERT_TRUE(third.ok());
  ASSERT_EQ(third->jobs.size(), 1u);
  EXPECT_TRUE(third->next_page_token.empty());

  absl::StatusOr<JobStore::Page> failed = store.List(Page(0, "", v1::FAILED), kT0);
  ASSERT_TRUE(failed.ok());
  ASSERT_EQ(failed->jobs.size(), 1u);
  EXPECT_EQ(failed->jobs[0].job->id(), "j1");
  EXPECT_EQ(store.CountByState().queued(), 4);
  EXPECT_EQ(store.CountByState().failed(), 1);
  EXPECT_EQ(store.List(Page(2, "x"), kT0).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST_P(JobStoreTest, EachListedJobCarriesTheTokenThatResumesAtIt) {
  std::unique_ptr<JobStore> owned = NewStore({});
  JobStore& store = *owned;
  for (int i = 0; i < 4; ++i) Add(store, JobRunHere(absl::StrCat("j", i), kT0), kT0);
  absl::StatusOr<JobStore::Page> all = store.List(Page(4, ""), kT0);
  ASSERT_TRUE(all.ok());
  ASSERT_EQ(all->jobs.size(), 4u);
  // A caller that cuts a page short (ListJobs does, by bytes) resumes at the first job it left.
  absl::StatusOr<JobStore::Page> resumed = store.List(Page(4, all->jobs[2].token), kT0);
  ASSERT_TRUE(resumed.ok());
  ASSERT_EQ(resumed->jobs.size(), 2u);
  EXPECT_EQ(resumed->jobs[0].job->id(), "j1");
  EXPECT_EQ(resumed->jobs[1].job->id(), "j0");
}

TEST_P(JobStoreTest, ListsOnlyVisibleJobsAndFillsPagesWithThem) {
  std::unique_ptr<JobStore> owned = NewStore({});
  JobStore& store = *owned;
  for (int i = 0; i < 6; ++i) Add(store, JobRunHere(absl::StrCat("j", i), kT0), kT0);
  JobStore::Query query = Page(2, "");
  query.visible = [](const Job& job) {
    return job.id() == "j0" || job.id() == "j2" || job.id() == "j5";
  };
  absl::StatusOr<JobStore::Page> first = store.List(query, kT0);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(first->jobs.size(), 2u);
  EXPECT_EQ(first->jobs[0].job->id(), "j5");
  EXPECT_EQ(first->jobs[1].job->id(), "j2");
  query.page_token = first->next_page_token;
  absl::StatusOr<JobStore::Page> second = store.List(query, kT0);
  ASSERT_TRUE(second.ok());
  ASSERT_EQ(second->jobs.size(), 1u);
  EXPECT_EQ(second->jobs[0].job->id(), "j0");
  EXPECT_TRUE(second->next_page_token.empty());
}

TEST_P(JobStoreTest, EvictsTheJobThatEndedFirstAndNeverAnActiveOne) {
  std::unique_ptr<JobStore> owned = NewStore({});
  JobStore& store = *owned;
  std::vector<std::shared_ptr<Job>> jobs;
  for (int i = 0; i < 3; ++i) {
    jobs.push_back(JobRunHere(absl::StrCat("j", i), kT0));
    Add(store, jobs.back(), kT0);
  }
  Finish(store, *jobs[2], kT0 + absl::Seconds(1));  // ended first, though added last
  Finish(store, *jobs[0], kT0 + absl::Seconds(2));
  ASSERT_TRUE(store.EvictOldestFinished());
  EXPECT_EQ(store.Find("j2", kT0), nullptr);
  EXPECT_NE(store.Find("j0", kT0), nullptr);
  ASSERT_TRUE(store.EvictOldestFinished());
  EXPECT_EQ(store.Find("j0", kT0), nullptr);
  EXPECT_FALSE(store.EvictOldestFinished()) << "j1 is still queued";
  EXPECT_NE(store.Find("j1", kT0), nullptr);
}

}  // namespace
}  // namespace ispq::server
