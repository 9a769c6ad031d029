// SPDX-License-Identifier: Apache-2.0
#include "server/admission/request_footprint.h"

#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"
#include "server/admission/request_bytes.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

StringRequestBytes BufferOf(const std::string& bytes) { return StringRequestBytes(bytes); }

absl::StatusOr<int64_t> Estimate(const google::protobuf::Message& message) {
  return EstimateParsedBytes(*message.GetDescriptor(), BufferOf(message.SerializeAsString()));
}

// The estimate is meant to bound the heap parsing takes; protobuf's own SpaceUsedLong leaves
// out the allocator's overhead (about a quarter more, measured), so the estimate must exceed it
// by that much, without being wildly above.
void ExpectBoundsTheParsedSize(const google::protobuf::Message& message) {
  const absl::StatusOr<int64_t> estimate = Estimate(message);
  ASSERT_TRUE(estimate.ok()) << estimate.status();
  std::unique_ptr<google::protobuf::Message> parsed(message.New());
  ASSERT_TRUE(parsed->ParseFromString(message.SerializeAsString()));
  const int64_t space_used = static_cast<int64_t>(parsed->SpaceUsedLong());
  EXPECT_GE(*estimate, space_used * 5 / 4) << message.GetDescriptor()->full_name();
  EXPECT_LE(*estimate, space_used * 4) << message.GetDescriptor()->full_name();
}

TEST(RequestFootprintTest, BoundsTheParsedSizeOfRealRequests) {
  for (const char* file :
       {"hex-me/s07c_notch.tmesh.json", "singularity-constrained-fields/fanpart.tmesh.json"}) {
    v1::QuantizeRequest request;
    *request.mutable_mesh() = testing::LoadProtoOrDie(testing::RealTMeshPath(file));
    request.mutable_options()->mutable_scaling()->set_level_percent(25);
    request.set_request_id("a-request-id");
    ExpectBoundsTheParsedSize(request);
  }
}

TEST(RequestFootprintTest, SeesTheAmplificationOfEmptyMessages) {
  v1::QuantizeRequest request;
  for (int i = 0; i < 100'000; ++i) request.mutable_mesh()->add_nodes();
  ExpectBoundsTheParsedSize(request);
  const absl::StatusOr<int64_t> estimate = Estimate(request);
  ASSERT_TRUE(estimate.ok());
  EXPECT_GT(*estimate, 25 * static_cast<int64_t>(request.ByteSizeLong()))
      << "two bytes on the wire are a whole Node in memory";
}

TEST(RequestFootprintTest, CountsPackedAndUnpackedRepeatedScalarsAndUnknownFields) {
  v1::QuantizeRequest request;
  v1::Node* node = request.mutable_mesh()->add_nodes();
  for (int i = 0; i < 10'000; ++i) node->add_outgoing_halfarcs(i * 1000);
  for (int i = 0; i < 5'000; ++i) node->add_position(i);
  request.mutable_mesh()
      ->GetReflection()
      ->MutableUnknownFields(request.mutable_mesh())
      ->AddLengthDelimited(999, std::string(5000, 'u'));
  ExpectBoundsTheParsedSize(request);
}

TEST(RequestFootprintTest, RefusesLongStringsNamingTheField) {
  v1::QuantizeRequest request;
  request.mutable_mesh()->set_name(std::string(1025, 'n'));
  EXPECT_THAT(std::string(Estimate(request).status().message()),
              HasSubstr("mesh.name is 1025 bytes long; at most 1024 are accepted"));
  request.mutable_mesh()->set_name(std::string(1024, 'n'));
  EXPECT_TRUE(Estimate(request).ok());
  v1::ListJobsRequest list;
  list.set_page_token(std::string(4096, '7'));
  EXPECT_THAT(std::string(Estimate(list).status().message()), HasSubstr("page_token is 4096"));
}

TEST(RequestFootprintTest, RefusesBytesThatAreNoMessageLikeTheParser) {
  for (const std::string& bytes : {std::string(16, '\xff'), std::string("\x0a\x05\x3a", 3),
                                   std::string("\x0b\x00", 2), std::string("\x00\x00", 2)}) {
    const absl::StatusOr<int64_t> estimate =
        EstimateParsedBytes(*v1::QuantizeRequest::descriptor(), BufferOf(bytes));
    EXPECT_EQ(estimate.status().message(),
              "the request is not a valid ispq.v1.QuantizeRequest message (binary protobuf)");
  }
  // A wire type that does not fit the field is an unknown field to protobuf, not an error.
  EXPECT_TRUE(
      EstimateParsedBytes(*v1::QuantizeRequest::descriptor(), BufferOf(std::string("\x08\x05", 2)))
          .ok());
}

}  // namespace
}  // namespace ispq::server
