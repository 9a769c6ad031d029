// SPDX-License-Identifier: Apache-2.0
// A gRPC request's bytes read in place (server/grpc/byte_buffer_bytes.h): over many slices, the
// footprint walk and the parse see what they see in one string, and each read starts anew.
#include "server/grpc/byte_buffer_bytes.h"

#include <string>
#include <vector>

#include "grpcpp/support/slice.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"
#include "server/admission/raw_request.h"
#include "server/admission/request_bytes.h"
#include "server/admission/request_footprint.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

constexpr char kNotch[] = "hex-me/s07c_notch.tmesh.json";

// `bytes` in slices of `slice_bytes` (the last one shorter).
grpc::ByteBuffer Sliced(const std::string& bytes, size_t slice_bytes) {
  std::vector<grpc::Slice> slices;
  for (size_t at = 0; at < bytes.size(); at += slice_bytes) {
    slices.emplace_back(bytes.substr(at, slice_bytes));
  }
  return grpc::ByteBuffer(slices.data(), slices.size());
}

TEST(ByteBufferBytesTest, ReadAcrossSlicesAsFromOneString) {
  v1::QuantizeRequest request;
  *request.mutable_mesh() = testing::LoadProtoOrDie(testing::RealTMeshPath(kNotch));
  request.set_request_id("batch-7");
  const std::string serialized = request.SerializeAsString();
  const StringRequestBytes whole(serialized);
  const absl::StatusOr<int64_t> expected =
      EstimateParsedBytes(*v1::QuantizeRequest::descriptor(), whole);
  ASSERT_TRUE(expected.ok()) << expected.status();

  for (const size_t slice_bytes : {size_t{1}, size_t{7}, size_t{4096}, serialized.size()}) {
    grpc::ByteBuffer buffer = Sliced(serialized, slice_bytes);
    const ByteBufferBytes bytes(buffer);
    EXPECT_EQ(buffer.Length(), 0u) << "the slices are taken";
    EXPECT_EQ(bytes.size(), static_cast<int64_t>(serialized.size()));
    const absl::StatusOr<int64_t> estimate =
        EstimateParsedBytes(*v1::QuantizeRequest::descriptor(), bytes);
    ASSERT_TRUE(estimate.ok()) << estimate.status();
    EXPECT_EQ(*estimate, *expected) << slice_bytes << "-byte slices";
    const absl::StatusOr<v1::QuantizeRequest> parsed = ParseRequest<v1::QuantizeRequest>(bytes);
    ASSERT_TRUE(parsed.ok()) << parsed.status();
    EXPECT_EQ(parsed->SerializeAsString(), serialized) << slice_bytes << "-byte slices";
  }
}

TEST(ByteBufferBytesTest, BytesThatAreNoMessageAreInvalidArgument) {
  grpc::ByteBuffer buffer = Sliced(std::string("\x0a\x05\x01", 3), 1);
  const ByteBufferBytes bytes(buffer);
  const absl::StatusOr<v1::QuantizeRequest> parsed = ParseRequest<v1::QuantizeRequest>(bytes);
  EXPECT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(parsed.status().message(),
            "the request is not a valid ispq.v1.QuantizeRequest message (binary protobuf)");
}

}  // namespace
}  // namespace ispq::server
