// SPDX-License-Identifier: Apache-2.0
#include "server/admission/memory_admission.h"

#include <memory>
#include <optional>
#include <string>

#include "absl/time/clock.h"
#include "core/proto/quantization_proto.h"
#include "core/quantization_validator.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/jobs/retry_hint.h"
#include "server/model/mesh_admission.h"
#include "tests/server/server_test_jobs.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

class MemoryAdmissionTest : public ::testing::Test {
 protected:
  static constexpr int64_t kLimit = 1 << 20;

  MemoryAdmissionTest()
      : budget_(kLimit),
        meshes_(100),
        scheduler_({.workers = 1, .max_queued_jobs = 10, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_) {}

  // Runs a real job to its end; the store then retains its result, accounted in the budget.
  std::shared_ptr<Job> FinishedJob() {
    absl::StatusOr<std::shared_ptr<Job>> job = scheduler_.Submit(NotchJobSpec(), false);
    EXPECT_TRUE(job.ok()) << job.status();
    while (!(*job)->done()) absl::SleepFor(absl::Milliseconds(1));
    const v1::Job proto = (*job)->ToProto(v1::FULL);
    const TMesh& mesh = *NotchJobSpec().mesh;
    const absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(proto.result(), mesh);
    EXPECT_TRUE(q.ok()) << q.status();
    const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, *q);
    EXPECT_TRUE(report.ok() && report->valid() && proto.result().valid());
    return *job;
  }

  std::string StoredMesh(int64_t bytes) {
    absl::StatusOr<MemoryReservation> memory =
        memory_.Reserve(MemoryUse::kStoredMeshes, bytes, "m");
    EXPECT_TRUE(memory.ok()) << memory.status();
    const v1::TMesh proto =
        testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
    absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(proto, 1000, *std::move(memory));
    EXPECT_TRUE(admitted.ok()) << admitted.status();
    return (*meshes_.Add(*std::move(admitted), proto, "owner", absl::Now()))->id;
  }

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
};

TEST_F(MemoryAdmissionTest, EvictsResultsOldestFirstThenUnusedMeshesLeastRecentlyUsed) {
  const std::shared_ptr<Job> older = FinishedJob();
  const std::shared_ptr<Job> newer = FinishedJob();
  EXPECT_GT(budget_.used(MemoryUse::kResults), 0);
  const std::string mesh_a = StoredMesh(kLimit / 4);
  const std::string mesh_b = StoredMesh(kLimit / 4);
  ASSERT_NE(meshes_.Find(mesh_a), nullptr);  // now b is the least recently used
  const int64_t results = budget_.used(MemoryUse::kResults);

  // Room for this needs the results gone and one mesh: b goes, a stays.
  const int64_t wanted = kLimit - budget_.used() + results + kLimit / 8;
  absl::StatusOr<MemoryReservation> reserved = memory_.Reserve(MemoryUse::kJobs, wanted, "a job");
  ASSERT_TRUE(reserved.ok()) << reserved.status();
  EXPECT_EQ(scheduler_.Find(older->id()), nullptr);
  EXPECT_EQ(scheduler_.Find(newer->id()), nullptr);
  EXPECT_EQ(meshes_.Find(mesh_b), nullptr);
  EXPECT_NE(meshes_.Find(mesh_a), nullptr);
  v1::ServerStats stats;
  metrics_.FillProto(stats);
  EXPECT_EQ(stats.evicted_results_total(), 2);
  EXPECT_EQ(stats.evicted_meshes_total(), 1);
  EXPECT_LE(budget_.used(), kLimit);
}

TEST_F(MemoryAdmissionTest, RefusesWithARetryHintOnlyWhatCouldFitLater) {
  MemoryReservation running = budget_.ForceReserve(MemoryUse::kJobs, kLimit / 2);
  const std::string mesh = StoredMesh(kLimit / 4);
  absl::StatusOr<MemoryReservation> later =
      memory_.Reserve(MemoryUse::kJobs, kLimit * 3 / 4, "the job");
  EXPECT_EQ(later.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(std::string(later.status().message()), HasSubstr("not enough memory for the job"));
  EXPECT_TRUE(RetryHintOf(later.status()).has_value());
  EXPECT_NE(meshes_.Find(mesh), nullptr) << "evicting could not have made room: nothing evicted";

  absl::StatusOr<MemoryReservation> never = memory_.Reserve(MemoryUse::kJobs, 2 * kLimit, "it");
  EXPECT_THAT(std::string(never.status().message()),
              HasSubstr("more than this server's whole memory budget"));
  EXPECT_FALSE(RetryHintOf(never.status()).has_value());
  v1::ServerStats stats;
  metrics_.FillProto(stats);
  EXPECT_EQ(stats.rejected_memory_total(), 2);
}

TEST_F(MemoryAdmissionTest, AccountingReceivedBytesRefusesWhenOverdrawn) {
  MemoryReservation running = budget_.ForceReserve(MemoryUse::kJobs, kLimit - 100);
  absl::StatusOr<MemoryReservation> small = memory_.Account(MemoryUse::kRequests, 50, "request");
  EXPECT_TRUE(small.ok()) << small.status();
  absl::StatusOr<MemoryReservation> large = memory_.Account(MemoryUse::kRequests, 500, "request");
  EXPECT_EQ(large.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(budget_.used(), kLimit - 50) << "a refused claim is not kept";
}

TEST_F(MemoryAdmissionTest, AMeshAJobHoldsIsNotEvicted) {
  const std::string mesh = StoredMesh(kLimit / 4);
  std::shared_ptr<const TMesh> held = meshes_.Find(mesh)->admitted.mesh;
  EXPECT_FALSE(meshes_.EvictLeastRecentlyUsed());
  held.reset();
  EXPECT_TRUE(meshes_.EvictLeastRecentlyUsed());
  EXPECT_EQ(budget_.used(MemoryUse::kStoredMeshes), 0) << "the mesh's memory left with it";
}

}  // namespace
}  // namespace ispq::server
