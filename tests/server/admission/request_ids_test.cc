// SPDX-License-Identifier: Apache-2.0
#include "server/admission/request_ids.h"

#include <memory>
#include <optional>
#include <string>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "gtest/gtest.h"
#include "server/admission/request_fingerprint.h"
#include "tests/server/server_test_jobs.h"

namespace ispq::server {
namespace {

// The server's retained jobs, as far as the ids see them: a map the test fills and empties.
class RequestIdsTest : public ::testing::Test {
 protected:
  RequestIdsTest()
      : ids_([this](const std::string& id) {
          const auto it = retained_.find(id);
          return it == retained_.end() ? nullptr : it->second;
        }) {}

  std::shared_ptr<Job> NewJob() {
    std::shared_ptr<Job> job = NewNotchJob(absl::StrCat("job", retained_.size()));
    retained_[job->id()] = job;
    return job;
  }

  static RequestIds::Waiter Into(std::optional<RequestIds::Outcome>& outcome) {
    return [&outcome](RequestIds::Outcome delivered) { outcome = std::move(delivered); };
  }

  absl::flat_hash_map<std::string, std::shared_ptr<Job>> retained_;
  RequestIds ids_;
};

TEST_F(RequestIdsTest, TheFirstCallAdmitsAndLaterOnesGetItsJob) {
  std::optional<RequestIds::Outcome> unused;
  RequestIds::Decision first = ids_.Begin("alice", "id-1", "print", Into(unused));
  ASSERT_TRUE(first.ticket.has_value());
  EXPECT_FALSE(first.outcome.has_value());
  // A retry while the first is still being admitted waits for it.
  std::optional<RequestIds::Outcome> waited;
  RequestIds::Decision during = ids_.Begin("alice", "id-1", "print", Into(waited));
  EXPECT_FALSE(during.ticket.has_value());
  EXPECT_FALSE(during.outcome.has_value());
  const std::shared_ptr<Job> job = NewJob();
  ids_.Complete(*first.ticket, job);
  ASSERT_TRUE(waited.has_value());
  ASSERT_TRUE(waited->ok());
  EXPECT_EQ(**waited, job);
  // A retry after the first was admitted gets the job at once.
  RequestIds::Decision after = ids_.Begin("alice", "id-1", "print", Into(unused));
  ASSERT_TRUE(after.outcome.has_value());
  EXPECT_EQ(after.outcome->value(), job);
  EXPECT_FALSE(unused.has_value());
}

TEST_F(RequestIdsTest, ADifferentRequestWithTheIdIsAlreadyExistsAndPrincipalsDoNotMix) {
  std::optional<RequestIds::Outcome> unused;
  RequestIds::Decision first = ids_.Begin("alice", "id-2", "print", Into(unused));
  ASSERT_TRUE(first.ticket.has_value());
  RequestIds::Decision other = ids_.Begin("alice", "id-2", "other", Into(unused));
  ASSERT_TRUE(other.outcome.has_value());
  EXPECT_EQ(other.outcome->status().code(), absl::StatusCode::kAlreadyExists);
  RequestIds::Decision bob = ids_.Begin("bob", "id-2", "other", Into(unused));
  EXPECT_TRUE(bob.ticket.has_value()) << "bob's id-2 is not alice's";
  ids_.Complete(*first.ticket, NewJob());
  RequestIds::Decision later = ids_.Begin("alice", "id-2", "other", Into(unused));
  ASSERT_TRUE(later.outcome.has_value());
  EXPECT_EQ(later.outcome->status().code(), absl::StatusCode::kAlreadyExists);
}

TEST_F(RequestIdsTest, AFailedFirstCallPassesItsErrorOnAndFreesTheId) {
  std::optional<RequestIds::Outcome> unused;
  std::optional<RequestIds::Outcome> waited;
  RequestIds::Decision first = ids_.Begin("alice", "id-3", "print", Into(unused));
  ASSERT_TRUE(first.ticket.has_value());
  ids_.Begin("alice", "id-3", "print", Into(waited));
  ids_.Complete(*first.ticket, absl::ResourceExhaustedError("queue full"));
  ASSERT_TRUE(waited.has_value());
  EXPECT_EQ(waited->status().code(), absl::StatusCode::kResourceExhausted);
  RequestIds::Decision retry = ids_.Begin("alice", "id-3", "print", Into(unused));
  EXPECT_TRUE(retry.ticket.has_value()) << "a new attempt";
}

TEST_F(RequestIdsTest, AnIdIsForgottenWithItsJob) {
  std::optional<RequestIds::Outcome> unused;
  RequestIds::Decision first = ids_.Begin("alice", "id-4", "print", Into(unused));
  const std::shared_ptr<Job> job = NewJob();
  ids_.Complete(*first.ticket, job);
  retained_.erase(job->id());  // the server no longer retains the job
  EXPECT_TRUE(ids_.Begin("alice", "id-4", "print", Into(unused)).ticket.has_value());
}

TEST(RequestFingerprintTest, EqualForEqualRequestsOnly) {
  v1::QuantizeRequest a;
  a.set_stored_mesh("meshes/abc");
  a.mutable_options()->mutable_scaling()->set_level_percent(10);
  v1::QuantizeRequest b = a;
  EXPECT_EQ(RequestFingerprint(a), RequestFingerprint(b));
  EXPECT_EQ(RequestFingerprint(a).size(), 32u);
  b.mutable_options()->mutable_scaling()->set_level_percent(11);
  EXPECT_NE(RequestFingerprint(a), RequestFingerprint(b));
}

TEST(RequestIdsFormatTest, AcceptsUuidsAndRefusesOtherShapes) {
  EXPECT_TRUE(ValidateRequestId("3f2b8c1e-9a4d-4e6f-8b2a-1c5d7e9f0a3b").ok());
  EXPECT_TRUE(ValidateRequestId("retry_7").ok());
  for (const std::string& bad : {std::string(), std::string(65, 'a'), std::string("a b"),
                                 std::string("a/b"), std::string("\xc3\xa9")}) {
    EXPECT_EQ(ValidateRequestId(bad).code(), absl::StatusCode::kInvalidArgument) << bad;
  }
}

}  // namespace
}  // namespace ispq::server
