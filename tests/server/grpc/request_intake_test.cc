// SPDX-License-Identifier: Apache-2.0
// TakeRequest (server/grpc/request_intake.h): a gRPC request's bytes are taken out of the call
// (gRPC would otherwise keep them until the call ends, for Quantize when the job ends) and
// accounted in the memory budget as received, within the method's size limit.
#include "server/grpc/request_intake.h"

#include <string>

#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"
#include "server/store/mesh_store.h"

namespace ispq::server {
namespace {

class RequestIntakeTest : public ::testing::Test {
 protected:
  RequestIntakeTest()
      : budget_(1 << 20),
        meshes_(10),
        scheduler_({.workers = 0, .max_queued_jobs = 1, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_) {}
  ~RequestIntakeTest() override { scheduler_.StopAccepting(); }

  static grpc::ByteBuffer BufferOf(const std::string& bytes) {
    grpc::Slice slice(bytes);
    return grpc::ByteBuffer(&slice, 1);
  }

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
};

TEST_F(RequestIntakeTest, TheBytesLeaveTheCallAccountedAsReceived) {
  v1::GetJobRequest request;
  request.set_name("jobs/0123456789abcdef");
  const std::string wire = request.SerializeAsString();
  const grpc::ByteBuffer call_request = BufferOf(wire);
  absl::StatusOr<RawRequest> raw = TakeRequest(&call_request, wire.size(), memory_);
  ASSERT_TRUE(raw.ok()) << raw.status();
  EXPECT_EQ(call_request.Length(), 0u) << "the call no longer holds the bytes";
  EXPECT_EQ(raw->size, static_cast<int64_t>(wire.size()));
  EXPECT_EQ(budget_.used(MemoryUse::kRequests), raw->size);
  const absl::StatusOr<v1::GetJobRequest> parsed = ParseRequest<v1::GetJobRequest>(*raw->bytes);
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->name(), request.name());
}

TEST_F(RequestIntakeTest, ARequestOverTheMethodsLimitIsRefusedAndNotAccounted) {
  const grpc::ByteBuffer call_request = BufferOf(std::string(100, 'x'));
  const absl::StatusOr<RawRequest> raw = TakeRequest(&call_request, 99, memory_);
  EXPECT_EQ(raw.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(budget_.used(), 0);
  const grpc::ByteBuffer too_large = BufferOf(std::string((1 << 20) + 1, 'x'));
  EXPECT_EQ(TakeRequest(&too_large, 1 << 30, memory_).status().code(),
            absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(budget_.used(), 0);
}

}  // namespace
}  // namespace ispq::server
