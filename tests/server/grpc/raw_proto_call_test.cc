// SPDX-License-Identifier: Apache-2.0
// SerializeMessage (server/grpc/raw_proto_call.h): a raw method's response buffer holds exactly
// the message afterwards, whatever it held before (a stream reuses one buffer for every event).
#include "server/grpc/raw_proto_call.h"

#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"

namespace ispq::server {
namespace {

std::string BytesOf(const grpc::ByteBuffer& buffer) {
  std::vector<grpc::Slice> slices;
  EXPECT_TRUE(buffer.Dump(&slices).ok());
  std::string bytes;
  for (const grpc::Slice& slice : slices) {
    bytes.append(reinterpret_cast<const char*>(slice.begin()), slice.size());
  }
  return bytes;
}

TEST(RawProtoCallTest, TheBufferHoldsTheMessageAndNothingOfWhatItHeldBefore) {
  grpc::Slice earlier(std::string(1000, 'x'));
  grpc::ByteBuffer buffer(&earlier, 1);
  v1::QuantizeEvent event;
  event.set_job("jobs/0123456789abcdef");
  event.set_sequence(7);
  ASSERT_TRUE(SerializeMessage(event, buffer).ok());
  EXPECT_EQ(BytesOf(buffer), event.SerializeAsString());

  // Reused for the next, smaller one.
  v1::QuantizeEvent next;
  next.set_sequence(8);
  ASSERT_TRUE(SerializeMessage(next, buffer).ok());
  EXPECT_EQ(BytesOf(buffer), next.SerializeAsString());
  ASSERT_TRUE(SerializeMessage(v1::QuantizeEvent(), buffer).ok());
  EXPECT_EQ(buffer.Length(), 0u);
}

}  // namespace
}  // namespace ispq::server
