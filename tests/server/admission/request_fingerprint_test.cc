// SPDX-License-Identifier: Apache-2.0
#include "server/admission/request_fingerprint.h"

#include <string>

#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"

namespace ispq::server {
namespace {

v1::QuantizeRequest Request(int level) {
  v1::QuantizeRequest request;
  request.set_stored_mesh("meshes/abc");
  request.mutable_options()->mutable_scaling()->set_level_percent(level);
  request.mutable_options()->set_per_arc_nonnegative(true);
  return request;
}

TEST(RequestFingerprintTest, EqualRequestsHaveEqualFingerprintsOfThirtyTwoBytes) {
  const std::string fingerprint = RequestFingerprint(Request(25));
  EXPECT_EQ(fingerprint.size(), 32u);
  EXPECT_EQ(RequestFingerprint(Request(25)), fingerprint);
  EXPECT_NE(RequestFingerprint(Request(50)), fingerprint);
}

// A client may serialize fields in any order; the fingerprint is of the message, not the bytes.
TEST(RequestFingerprintTest, DoesNotDependOnTheOrderTheClientSerializedIn) {
  v1::QuantizeRequest options_first;
  options_first.mutable_options()->set_per_arc_nonnegative(true);
  options_first.mutable_options()->mutable_scaling()->set_level_percent(25);
  options_first.set_stored_mesh("meshes/abc");
  std::string reordered;
  ASSERT_TRUE(options_first.options().SerializeToString(&reordered));
  // Field 3 (options) before field 2 (stored_mesh) on the wire.
  std::string wire =
      std::string("\x1a") + static_cast<char>(reordered.size()) + reordered + "\x12\x0ameshes/abc";
  v1::QuantizeRequest parsed;
  ASSERT_TRUE(parsed.ParseFromString(wire));
  EXPECT_EQ(RequestFingerprint(parsed), RequestFingerprint(Request(25)));
}

}  // namespace
}  // namespace ispq::server
