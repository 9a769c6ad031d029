// SPDX-License-Identifier: Apache-2.0
// How a request enters the server within the memory budget (server/admission/raw_request.h): its
// bytes accounted as received, a method's size limit, parsing with the parsed size reserved
// first, and no memory held by a request once it is refused or parsed: the raw bytes are let go
// whether parsing succeeded or not.
#include "server/admission/raw_request.h"

#include <memory>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"
#include "server/store/mesh_store.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

std::unique_ptr<RequestBytes> BytesOf(const std::string& bytes) {
  return std::make_unique<StringRequestBytes>(bytes);
}

std::string GetJobBytes() {
  v1::GetJobRequest request;
  request.set_name("jobs/0123456789abcdef");
  request.set_view(v1::FULL);
  return request.SerializeAsString();
}

// Bytes that are not a message of any type: a field number 0.
const std::string kNotAMessage = std::string("\x00\x01\x02", 3);

class RawRequestTest : public ::testing::Test {
 protected:
  static constexpr int64_t kLimit = 512 << 10;

  RawRequestTest()
      : budget_(kLimit),
        meshes_(10),
        scheduler_({.workers = 0, .max_queued_jobs = 1, .retention = {}}, metrics_, &budget_),
        memory_(budget_, scheduler_, meshes_, metrics_) {}
  ~RawRequestTest() override { scheduler_.StopAccepting(); }

  ServerMetrics metrics_;
  MemoryBudget budget_;
  InMemoryMeshStore meshes_;
  JobScheduler scheduler_;
  MemoryAdmission memory_;
};

TEST_F(RawRequestTest, TheBytesAreAccountedAsRequestsUntilLetGo) {
  const std::string wire = GetJobBytes();
  absl::StatusOr<RawRequest> raw = AccountRequest(BytesOf(wire), wire.size(), memory_);
  ASSERT_TRUE(raw.ok()) << raw.status();
  EXPECT_EQ(raw->size, static_cast<int64_t>(wire.size()));
  EXPECT_EQ(raw->memory.bytes(), raw->size);
  EXPECT_EQ(budget_.used(MemoryUse::kRequests), raw->size);
  Discard(*raw);
  EXPECT_EQ(raw->bytes, nullptr);
  EXPECT_EQ(budget_.used(), 0);
}

TEST_F(RawRequestTest, AMethodsSizeLimitIsInvalidArgumentAndAccountsNothing) {
  const std::string wire = GetJobBytes();
  const absl::StatusOr<RawRequest> raw = AccountRequest(BytesOf(wire), wire.size() - 1, memory_);
  EXPECT_EQ(raw.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(raw.status().message()),
              HasSubstr(absl::StrCat("the request is ", wire.size(), " bytes")));
  EXPECT_EQ(budget_.used(), 0);
}

TEST_F(RawRequestTest, BytesBeyondTheBudgetAreResourceExhaustedAndNotKept) {
  const absl::StatusOr<RawRequest> raw =
      AccountRequest(BytesOf(std::string(kLimit + 1, 'x')), kLimit * 2, memory_);
  EXPECT_EQ(raw.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(budget_.used(), 0);
}

TEST_F(RawRequestTest, ParsingNamesTheMessageTypeItExpected) {
  const absl::StatusOr<v1::GetJobRequest> parsed =
      ParseRequest<v1::GetJobRequest>(StringRequestBytes(kNotAMessage));
  EXPECT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(parsed.status().message()), HasSubstr("ispq.v1.GetJobRequest"));
  const absl::StatusOr<v1::GetJobRequest> good =
      ParseRequest<v1::GetJobRequest>(StringRequestBytes(GetJobBytes()));
  ASSERT_TRUE(good.ok()) << good.status();
  EXPECT_EQ(good->name(), "jobs/0123456789abcdef");
}

// The parsed message holds its estimated size in place of the bytes it came from.
TEST_F(RawRequestTest, AParsedRequestHoldsItsParsedSizeInsteadOfItsBytes) {
  const std::string wire = GetJobBytes();
  absl::StatusOr<RawRequest> raw = AccountRequest(BytesOf(wire), 1 << 20, memory_);
  ASSERT_TRUE(raw.ok()) << raw.status();
  const absl::StatusOr<int64_t> estimate =
      EstimateParsedBytes(*v1::GetJobRequest::descriptor(), StringRequestBytes(wire));
  ASSERT_TRUE(estimate.ok()) << estimate.status();

  absl::StatusOr<ParsedRequest<v1::GetJobRequest>> parsed =
      ParseWithinBudget<v1::GetJobRequest>(*raw, memory_);
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->message.SerializeAsString(), wire);
  EXPECT_EQ(raw->bytes, nullptr) << "the raw bytes are let go once parsed";
  EXPECT_EQ(parsed->memory.bytes(), *estimate);
  EXPECT_EQ(budget_.used(MemoryUse::kRequests), *estimate);
  parsed->memory.Release();
  EXPECT_EQ(budget_.used(), 0);
}

TEST_F(RawRequestTest, ARequestThatDoesNotParseHoldsNoMemory) {
  absl::StatusOr<RawRequest> raw = AccountRequest(BytesOf(kNotAMessage), 1 << 20, memory_);
  ASSERT_TRUE(raw.ok()) << raw.status();
  const absl::StatusOr<ParsedRequest<v1::GetJobRequest>> parsed =
      ParseWithinBudget<v1::GetJobRequest>(*raw, memory_);
  EXPECT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(raw->bytes, nullptr);
  EXPECT_EQ(budget_.used(), 0);
}

// Parsing amplifies: empty arcs are 2 bytes on the wire each and far more once parsed. The
// bytes fit the budget, their parsed size does not; the request is refused before it is parsed.
TEST_F(RawRequestTest, ARequestWhoseParsedSizeDoesNotFitIsRefusedBeforeParsing) {
  v1::QuantizeRequest request;
  for (int i = 0; i < 20000; ++i) request.mutable_mesh()->add_arcs();
  const std::string wire = request.SerializeAsString();
  ASSERT_LT(static_cast<int64_t>(wire.size()), kLimit / 4);
  absl::StatusOr<RawRequest> raw = AccountRequest(BytesOf(wire), 1 << 30, memory_);
  ASSERT_TRUE(raw.ok()) << raw.status();
  const absl::StatusOr<ParsedRequest<v1::QuantizeRequest>> parsed =
      ParseWithinBudget<v1::QuantizeRequest>(*raw, memory_);
  EXPECT_EQ(parsed.status().code(), absl::StatusCode::kResourceExhausted);
  EXPECT_THAT(std::string(parsed.status().message()), HasSubstr("parsing the request"));
  EXPECT_EQ(raw->bytes, nullptr);
  EXPECT_EQ(budget_.used(), 0);
}

}  // namespace
}  // namespace ispq::server
