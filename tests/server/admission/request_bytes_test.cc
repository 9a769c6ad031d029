// SPDX-License-Identifier: Apache-2.0
// StringRequestBytes (server/admission/request_bytes.h): a request's bytes are walked for their
// footprint and then parsed, so every Read must yield all of them from the first, whatever an
// earlier stream consumed.
#include "server/admission/request_bytes.h"

#include <memory>
#include <string>

#include "google/protobuf/io/zero_copy_stream.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"

namespace ispq::server {
namespace {

// Everything `stream` yields.
std::string Drain(google::protobuf::io::ZeroCopyInputStream& stream) {
  std::string bytes;
  const void* data = nullptr;
  int size = 0;
  while (stream.Next(&data, &size)) bytes.append(static_cast<const char*>(data), size);
  return bytes;
}

TEST(RequestBytesTest, EachReadStartsAnewOverAllTheBytes) {
  v1::GetJobRequest request;
  request.set_name("jobs/0123456789abcdef");
  const std::string wire = request.SerializeAsString();
  const StringRequestBytes bytes(wire);
  EXPECT_EQ(bytes.size(), static_cast<int64_t>(wire.size()));

  const std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> walk = bytes.Read();
  EXPECT_EQ(Drain(*walk), wire);
  // A second stream while the first is exhausted, as the parse after the footprint walk.
  const std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> parse = bytes.Read();
  v1::GetJobRequest parsed;
  ASSERT_TRUE(parsed.ParseFromZeroCopyStream(parse.get()));
  EXPECT_EQ(parsed.name(), request.name());
}

TEST(RequestBytesTest, NoBytesAreAnEmptyStream) {
  const StringRequestBytes bytes("");
  EXPECT_EQ(bytes.size(), 0);
  EXPECT_EQ(Drain(*bytes.Read()), "");
}

}  // namespace
}  // namespace ispq::server
