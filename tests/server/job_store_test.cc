#include "server/job_store.h"

#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"

namespace ispq::server {
namespace {

const absl::Time kT0 = absl::FromUnixSeconds(1'000'000);

void Finish(Job& job, absl::Time when) {
  job.FinishWithError(absl::InternalError("done for the test"), when);
}

TEST(JobStoreTest, KeepsActiveJobsAndTheNewestFinishedOnes) {
  JobStore store({.max_finished = 2, .max_age = absl::Hours(1)});
  std::vector<std::shared_ptr<Job>> jobs;
  for (int i = 0; i < 4; ++i) {
    jobs.push_back(NewNotchJob(absl::StrCat("job", i), kT0));
    store.Add(jobs.back(), kT0);
  }
  Finish(*jobs[0], kT0 + absl::Seconds(1));
  Finish(*jobs[1], kT0 + absl::Seconds(2));
  Finish(*jobs[2], kT0 + absl::Seconds(3));
  const absl::Time now = kT0 + absl::Seconds(4);
  EXPECT_EQ(store.Find("job0", now), nullptr);  // the oldest finished beyond the count
  EXPECT_NE(store.Find("job1", now), nullptr);
  EXPECT_NE(store.Find("job2", now), nullptr);
  EXPECT_NE(store.Find("job3", now), nullptr);  // running jobs are never evicted
  EXPECT_EQ(store.ActiveJobs().size(), 1u);
}

TEST(JobStoreTest, ForgetsFinishedJobsAfterTheRetentionTime) {
  JobStore store({.max_finished = 100, .max_age = absl::Minutes(10)});
  std::shared_ptr<Job> job = NewNotchJob("old", kT0);
  store.Add(job, kT0);
  Finish(*job, kT0);
  EXPECT_NE(store.Find("old", kT0 + absl::Minutes(10)), nullptr);
  EXPECT_EQ(store.Find("old", kT0 + absl::Minutes(10) + absl::Seconds(1)), nullptr);
}

TEST(JobStoreTest, ListsNewestFirstInPagesAndByState) {
  JobStore store({});
  for (int i = 0; i < 5; ++i) store.Add(NewNotchJob(absl::StrCat("j", i), kT0), kT0);
  Finish(*store.Find("j1", kT0), kT0);
  absl::StatusOr<JobStore::Page> first = store.List(2, "", v1::JOB_STATE_UNSPECIFIED, kT0);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(first->jobs.size(), 2u);
  EXPECT_EQ(first->jobs[0]->id(), "j4");
  EXPECT_EQ(first->jobs[1]->id(), "j3");
  absl::StatusOr<JobStore::Page> second =
      store.List(2, first->next_page_token, v1::JOB_STATE_UNSPECIFIED, kT0);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second->jobs[0]->id(), "j2");
  EXPECT_EQ(second->jobs[1]->id(), "j1");
  absl::StatusOr<JobStore::Page> third =
      store.List(2, second->next_page_token, v1::JOB_STATE_UNSPECIFIED, kT0);
  ASSERT_TRUE(third.ok());
  ASSERT_EQ(third->jobs.size(), 1u);
  EXPECT_TRUE(third->next_page_token.empty());

  absl::StatusOr<JobStore::Page> failed = store.List(0, "", v1::FAILED, kT0);
  ASSERT_TRUE(failed.ok());
  ASSERT_EQ(failed->jobs.size(), 1u);
  EXPECT_EQ(failed->jobs[0]->id(), "j1");
  EXPECT_EQ(store.CountByState().queued(), 4);
  EXPECT_EQ(store.CountByState().failed(), 1);
  EXPECT_EQ(store.List(2, "x", v1::JOB_STATE_UNSPECIFIED, kT0).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace ispq::server
