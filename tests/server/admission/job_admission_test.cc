// SPDX-License-Identifier: Apache-2.0
// Admission of a QuantizeRequest as a job's specification (server/admission/job_admission.h):
// everything a client can get wrong is refused before the job exists (no mesh, an oversized or
// invalid mesh, bad options, bad report intervals, a stored mesh it may not use), the server's
// time limit caps the request's, and the mesh and the solver's working memory are reserved in
// the budget, with nothing left reserved by a refused request.
#include "server/admission/job_admission.h"

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/memory/memory_estimates.h"
#include "server/model/mesh_admission.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

v1::TMesh Notch() {
  return testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
}

v1::QuantizeRequest NotchRequest() {
  v1::QuantizeRequest request;
  *request.mutable_mesh() = Notch();
  request.mutable_options()->mutable_scaling()->set_level_percent(25);
  return request;
}

google::protobuf::Duration DurationOf(int64_t seconds, int32_t nanos) {
  google::protobuf::Duration duration;
  duration.set_seconds(seconds);
  duration.set_nanos(nanos);
  return duration;
}

class JobAdmissionTest : public ::testing::Test {
 protected:
  explicit JobAdmissionTest(int64_t budget_bytes = 1 << 30)
      : budget_(budget_bytes),
        meshes_(10),
        scheduler_({.workers = 0, .max_queued_jobs = 1, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_) {}
  ~JobAdmissionTest() override { scheduler_.StopAccepting(); }

  absl::StatusOr<JobSpec> Prepare(const v1::QuantizeRequest& request,
                                  const Principal& principal = Principal{.name = "alice"}) {
    const AdmissionContext context{limits_, principal, meshes_, memory_};
    return PrepareJobSpec(request, static_cast<int64_t>(request.ByteSizeLong()), context);
  }

  // A mesh alice stored, by name.
  std::string StoreNotch() {
    absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(Notch(), 1000000);
    EXPECT_TRUE(admitted.ok()) << admitted.status();
    return absl::StrCat("meshes/",
                        (*meshes_.Add(*std::move(admitted), Notch(), "alice", absl::Now()))->id);
  }

  JobLimits limits_{.max_arcs = 1000000, .max_job_time = absl::Seconds(600)};
  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
};

TEST_F(JobAdmissionTest, AnInlineMeshBecomesAJobsSpecificationWithItsMemoryReserved) {
  v1::QuantizeRequest request = NotchRequest();
  request.set_request_id("batch-7");
  absl::StatusOr<JobSpec> spec = Prepare(request);
  ASSERT_TRUE(spec.ok()) << spec.status();
  ASSERT_NE(spec->mesh, nullptr);
  EXPECT_EQ(spec->mesh->num_arcs(), request.mesh().arcs_size());
  EXPECT_EQ(spec->mesh_stats.arcs(), request.mesh().arcs_size());
  EXPECT_TRUE(spec->stored_mesh.empty());
  EXPECT_EQ(spec->owner, "alice");
  EXPECT_EQ(spec->request_id, "batch-7");
  EXPECT_EQ(spec->requested_options.SerializeAsString(), request.options().SerializeAsString());
  EXPECT_GT(spec->options.scaling, 0);

  const int64_t solver = SolverBytes(SolveSizeOf(spec->mesh_stats, spec->options));
  EXPECT_EQ(spec->memory.bytes(), solver);
  EXPECT_EQ(budget_.used(MemoryUse::kJobs),
            solver + MeshBytes(static_cast<int64_t>(request.ByteSizeLong())));
  spec->memory.Release();
  spec->mesh.reset();
  EXPECT_EQ(budget_.used(), 0) << "the mesh's reservation goes with the mesh";
}

TEST_F(JobAdmissionTest, WhatAClientGetsWrongIsRefusedWithNothingReserved) {
  struct Case {
    std::string what;
    std::function<void(v1::QuantizeRequest&)> change;
    std::string message;  // what the refusal names
  };
  const std::vector<Case> cases = {
      {"no mesh", [](v1::QuantizeRequest& r) { r.clear_mesh(); }, "no mesh given"},
      {"an invalid mesh",
       [](v1::QuantizeRequest& r) { r.mutable_mesh()->mutable_arcs(3)->set_length(-1); }, "arc 3"},
      {"no scaling", [](v1::QuantizeRequest& r) { r.mutable_options()->clear_scaling(); },
       "scaling"},
      {"a negative progress interval",
       [](v1::QuantizeRequest& r) { *r.mutable_progress_interval() = DurationOf(-1, 0); },
       "progress_interval"},
      {"negative nanos",
       [](v1::QuantizeRequest& r) { *r.mutable_progress_interval() = DurationOf(0, -5); },
       "progress_interval"},
      {"nanos of a second or more",
       [](v1::QuantizeRequest& r) {
         *r.mutable_intermediate_interval() = DurationOf(0, 1'000'000'000);
       },
       "intermediate_interval"},
  };
  for (const Case& bad : cases) {
    SCOPED_TRACE(bad.what);
    v1::QuantizeRequest request = NotchRequest();
    bad.change(request);
    const absl::StatusOr<JobSpec> spec = Prepare(request);
    EXPECT_EQ(spec.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(std::string(spec.status().message()), HasSubstr(bad.message));
    EXPECT_EQ(budget_.used(), 0);
  }
}

TEST_F(JobAdmissionTest, AMeshOverTheArcLimitIsRefusedBeforeMemoryIsReserved) {
  const v1::QuantizeRequest request = NotchRequest();
  limits_.max_arcs = request.mesh().arcs_size() - 1;
  const absl::StatusOr<JobSpec> spec = Prepare(request);
  EXPECT_EQ(spec.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr("--max_arcs"));
  EXPECT_EQ(budget_.ToProto().peak_used_bytes(), 0);
}

TEST_F(JobAdmissionTest, TheServersTimeLimitCapsTheRequestsOwn) {
  limits_.max_job_time = absl::Seconds(10);
  v1::QuantizeRequest request = NotchRequest();
  absl::StatusOr<JobSpec> unlimited = Prepare(request);
  ASSERT_TRUE(unlimited.ok()) << unlimited.status();
  EXPECT_EQ(unlimited->options.time_limit_seconds, 10);
  *request.mutable_options()->mutable_time_limit() = DurationOf(1000, 0);
  EXPECT_EQ(Prepare(request)->options.time_limit_seconds, 10);
  *request.mutable_options()->mutable_time_limit() = DurationOf(2, 500'000'000);
  EXPECT_EQ(Prepare(request)->options.time_limit_seconds, 2.5);
}

// Unset: 100 ms of progress and no intermediate results; zero intermediate: none; anything
// below 10 ms counts as 10 ms (zero progress too: progress is always reported).
TEST_F(JobAdmissionTest, ReportIntervalsHaveDefaultsAndAFloor) {
  v1::QuantizeRequest request = NotchRequest();
  absl::StatusOr<JobSpec> unset = Prepare(request);
  ASSERT_TRUE(unset.ok()) << unset.status();
  EXPECT_EQ(unset->progress_interval, kDefaultProgressInterval);
  EXPECT_EQ(unset->intermediate_interval, absl::ZeroDuration());

  *request.mutable_progress_interval() = DurationOf(0, 0);
  *request.mutable_intermediate_interval() = DurationOf(0, 0);
  absl::StatusOr<JobSpec> zero = Prepare(request);
  ASSERT_TRUE(zero.ok()) << zero.status();
  EXPECT_EQ(zero->progress_interval, kMinReportInterval);
  EXPECT_EQ(zero->intermediate_interval, absl::ZeroDuration());

  *request.mutable_progress_interval() = DurationOf(0, 1);
  *request.mutable_intermediate_interval() = DurationOf(0, 1);
  absl::StatusOr<JobSpec> tiny = Prepare(request);
  ASSERT_TRUE(tiny.ok()) << tiny.status();
  EXPECT_EQ(tiny->progress_interval, kMinReportInterval);
  EXPECT_EQ(tiny->intermediate_interval, kMinReportInterval);

  *request.mutable_progress_interval() = DurationOf(2, 250'000'000);
  *request.mutable_intermediate_interval() = DurationOf(5, 0);
  absl::StatusOr<JobSpec> slow = Prepare(request);
  ASSERT_TRUE(slow.ok()) << slow.status();
  EXPECT_EQ(slow->progress_interval, absl::Milliseconds(2250));
  EXPECT_EQ(slow->intermediate_interval, absl::Seconds(5));
}

// A stored mesh is shared, not admitted again: the job reserves only its solver memory.
TEST_F(JobAdmissionTest, AStoredMeshIsUsedByItsOwnerAndAdmins) {
  const std::string name = StoreNotch();
  v1::QuantizeRequest request = NotchRequest();
  request.set_stored_mesh(name);
  const int64_t stored_bytes = budget_.used();
  absl::StatusOr<JobSpec> spec = Prepare(request);
  ASSERT_TRUE(spec.ok()) << spec.status();
  EXPECT_EQ(spec->stored_mesh, name);
  EXPECT_EQ(spec->mesh, meshes_.Find(name.substr(7))->admitted.mesh);
  EXPECT_EQ(budget_.used() - stored_bytes, spec->memory.bytes());

  EXPECT_TRUE(Prepare(request, Principal{.name = "root", .admin = true}).ok());
}

// Another principal's mesh is NOT_FOUND with the same message as a mesh that never existed, so
// that names do not reveal other principals' meshes.
TEST_F(JobAdmissionTest, AnotherPrincipalsStoredMeshIsNotFoundLikeAnUnknownOne) {
  const std::string name = StoreNotch();
  const absl::StatusOr<std::shared_ptr<const StoredMesh>> bobs =
      FindStoredMesh(name, Principal{.name = "bob"}, meshes_);
  EXPECT_EQ(bobs.status().code(), absl::StatusCode::kNotFound);
  const std::string unknown = "meshes/0000000000000000";
  const absl::StatusOr<std::shared_ptr<const StoredMesh>> never =
      FindStoredMesh(unknown, Principal{.name = "bob"}, meshes_);
  EXPECT_EQ(never.status().code(), absl::StatusCode::kNotFound);
  std::string bobs_message(bobs.status().message());
  bobs_message.replace(bobs_message.find(name), name.size(), unknown);
  EXPECT_EQ(bobs_message, never.status().message());

  v1::QuantizeRequest request = NotchRequest();
  request.set_stored_mesh(name);
  EXPECT_EQ(Prepare(request, Principal{.name = "bob"}).status().code(),
            absl::StatusCode::kNotFound);
  request.set_stored_mesh("jobs/0000000000000000");
  EXPECT_EQ(Prepare(request).status().code(), absl::StatusCode::kInvalidArgument);
}

class JobAdmissionInASmallBudgetTest : public JobAdmissionTest {
 protected:
  // Room for the notch's mesh, not for its solver working memory.
  JobAdmissionInASmallBudgetTest() : JobAdmissionTest(256 << 10) {}
};

TEST_F(JobAdmissionInASmallBudgetTest, AJobTheBudgetCannotHoldIsRefusedAndReleasesItsMesh) {
  const v1::QuantizeRequest request = NotchRequest();
  ASSERT_LT(MeshBytes(static_cast<int64_t>(request.ByteSizeLong())), budget_.limit());
  const absl::StatusOr<JobSpec> spec = Prepare(request);
  EXPECT_EQ(spec.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(std::string(spec.status().message()), HasSubstr("solver working memory"));
  EXPECT_EQ(budget_.used(), 0);
}

}  // namespace
}  // namespace ispq::server
