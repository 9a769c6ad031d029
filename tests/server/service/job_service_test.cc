// SPDX-License-Identifier: Apache-2.0
// The service's transport-neutral operations (server/service/job_service.h), which both the
// gRPC adapter (server/grpc/quantizer_service.h) and the HTTP side call, on the in-memory stores
// and without a server: a submitted job runs to a valid result; jobs are visible only to their
// owner and to admins, NOT_FOUND for everyone else; a request id names one job however often it is
// submitted; an invalid request is INVALID_ARGUMENT naming what is wrong. The gRPC methods around
// them are tested end to end in tests/integration.
#include "server/service/job_service.h"

#include <memory>
#include <string>
#include <vector>

#include "absl/synchronization/notification.h"
#include "core/proto/quantization_proto.h"
#include "core/quantization_validator.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/admission/request_bytes.h"
#include "server/store/mesh_store.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

constexpr char kNotch[] = "hex-me/s07c_notch.tmesh.json";

v1::QuantizeRequest NotchRequest(const std::string& request_id = "") {
  v1::QuantizeRequest request;
  *request.mutable_mesh() = testing::LoadProtoOrDie(testing::RealTMeshPath(kNotch));
  request.mutable_options()->mutable_scaling()->set_level_percent(25);
  request.set_request_id(request_id);
  return request;
}

class JobServiceTest : public ::testing::Test {
 protected:
  explicit JobServiceTest(int workers = 1)
      : budget_(1 << 30),
        meshes_(10),
        scheduler_({.workers = workers, .max_queued_jobs = 8, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_),
        service_({scheduler_, meshes_, metrics_, memory_}, JobLimits{.max_arcs = 1000000},
                 AdmissionConfig{}) {}

  // Submits as `owner` and waits for the answer.
  JobSubmission::Outcome Submit(const v1::QuantizeRequest& request, const std::string& owner) {
    const std::string bytes = request.SerializeAsString();
    JobSubmission submission;
    submission.principal = Principal{.name = owner};
    submission.raw.bytes = std::make_unique<StringRequestBytes>(bytes);
    submission.raw.size = static_cast<int64_t>(bytes.size());
    submission.peer = "test";
    absl::Notification answered;
    JobSubmission::Outcome outcome = absl::UnknownError("never answered");
    submission.answer = [&](const JobSubmission::Outcome& o) {
      outcome = o;
      answered.Notify();
    };
    service_.Submit(std::move(submission));
    EXPECT_TRUE(answered.WaitForNotificationWithTimeout(testing::kSafetyNet));
    return outcome;
  }

  absl::StatusOr<v1::Job> Get(const std::string& name, const std::string& who) {
    v1::GetJobRequest request;
    request.set_name(name);
    request.set_view(v1::FULL);
    return service_.GetJob(request, Principal{.name = who, .admin = who == "admin"});
  }

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
  JobService service_;
};

TEST_F(JobServiceTest, ASubmittedJobRunsToAValidResultItsOwnerCanGet) {
  const JobSubmission::Outcome job = Submit(NotchRequest(), "alice");
  ASSERT_TRUE(job.ok()) << job.status();
  ASSERT_TRUE(testing::WaitUntil([&] { return (*job)->done(); }));
  const absl::StatusOr<v1::Job> got = Get((*job)->name(), "alice");
  ASSERT_TRUE(got.ok()) << got.status();
  EXPECT_EQ(got->state(), v1::SUCCEEDED);
  EXPECT_EQ(got->owner(), "alice");
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath(kNotch));
  const absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(got->result(), mesh);
  ASSERT_TRUE(q.ok()) << q.status();
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, *q);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_TRUE(report->valid()) << report->Describe();
}

TEST_F(JobServiceTest, JobsAreVisibleToTheirOwnerAndAdminsOnly) {
  const JobSubmission::Outcome job = Submit(NotchRequest(), "alice");
  ASSERT_TRUE(job.ok()) << job.status();
  const std::string name = (*job)->name();
  EXPECT_TRUE(Get(name, "alice").ok());
  EXPECT_TRUE(Get(name, "admin").ok());
  EXPECT_EQ(Get(name, "bob").status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(Get("jobs/0000000000000000", "alice").status().code(), absl::StatusCode::kNotFound);

  const absl::StatusOr<v1::ListJobsResponse> bobs =
      service_.ListJobs(v1::ListJobsRequest(), Principal{.name = "bob"});
  ASSERT_TRUE(bobs.ok()) << bobs.status();
  EXPECT_EQ(bobs->jobs_size(), 0);
  const absl::StatusOr<v1::ListJobsResponse> alices =
      service_.ListJobs(v1::ListJobsRequest(), Principal{.name = "alice"});
  ASSERT_TRUE(alices.ok()) << alices.status();
  ASSERT_EQ(alices->jobs_size(), 1);
  EXPECT_EQ(alices->jobs(0).name(), name);

  v1::CancelJobRequest cancel;
  cancel.set_name(name);
  EXPECT_EQ(service_.CancelJob(cancel, Principal{.name = "bob"}).status().code(),
            absl::StatusCode::kNotFound);
  v1::WatchJobRequest watch;
  watch.set_name(name);
  EXPECT_EQ(service_.Watch(watch, Principal{.name = "bob"}).status().code(),
            absl::StatusCode::kNotFound);
  const absl::StatusOr<WatchTarget> target = service_.Watch(watch, Principal{.name = "alice"});
  ASSERT_TRUE(target.ok()) << target.status();
  EXPECT_EQ(target->job, *job);
}

TEST_F(JobServiceTest, ARequestIdNamesOneJobPerPrincipal) {
  const JobSubmission::Outcome first = Submit(NotchRequest("batch-7"), "alice");
  const JobSubmission::Outcome again = Submit(NotchRequest("batch-7"), "alice");
  const JobSubmission::Outcome bobs = Submit(NotchRequest("batch-7"), "bob");
  ASSERT_TRUE(first.ok() && again.ok() && bobs.ok());
  EXPECT_EQ(*again, *first);
  EXPECT_NE(*bobs, *first);

  v1::QuantizeRequest changed = NotchRequest("batch-7");
  changed.mutable_options()->mutable_scaling()->set_level_percent(50);
  const JobSubmission::Outcome conflicting = Submit(changed, "alice");
  EXPECT_FALSE(conflicting.ok()) << "a request id reused for another request is refused";
}

TEST_F(JobServiceTest, AnInvalidRequestNamesWhatIsWrong) {
  v1::QuantizeRequest request = NotchRequest();
  request.mutable_mesh()->mutable_arcs(3)->set_length(-1);
  const JobSubmission::Outcome refused = Submit(request, "alice");
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(refused.status().message()), HasSubstr("arc 3"));
}

class JobServiceWithoutWorkersTest : public JobServiceTest {
 protected:
  JobServiceWithoutWorkersTest() : JobServiceTest(/*workers=*/0) {}
};

TEST_F(JobServiceWithoutWorkersTest, TheOwnerCancelsAQueuedJob) {
  const JobSubmission::Outcome job = Submit(NotchRequest(), "alice");
  ASSERT_TRUE(job.ok()) << job.status();
  v1::CancelJobRequest cancel;
  cancel.set_name((*job)->name());
  const absl::StatusOr<v1::Job> cancelled = service_.CancelJob(cancel, Principal{.name = "alice"});
  ASSERT_TRUE(cancelled.ok()) << cancelled.status();
  EXPECT_EQ(cancelled->state(), v1::CANCELLED);
  EXPECT_TRUE(cancelled->done());
}

}  // namespace
}  // namespace ispq::server
