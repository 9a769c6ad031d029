// SPDX-License-Identifier: Apache-2.0
// MessageToJson writes every field, defaults included (valid: false, zero counts, empty lists
// are answers), under the JSON names of the mapping, and what it writes parses back.
#include "client/message_json.h"

#include <string>

#include "gmock/gmock.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "ispq/v1/mesh_stats.pb.h"
#include "ispq/v1/quantization.pb.h"

namespace ispq::cli {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

TEST(MessageJsonTest, DefaultValuesAreWrittenToo) {
  const std::string json = MessageToJson(v1::QuantizationResult());
  EXPECT_THAT(json, HasSubstr("\"valid\":false"));
  EXPECT_THAT(json, HasSubstr("\"q\":[]"));
  EXPECT_THAT(json, HasSubstr("\"hexes\":\"0\""));  // int64 as a string, per the mapping
  EXPECT_THAT(json, HasSubstr("\"meshName\":\"\""));
  const std::string stats = MessageToJson(v1::MeshStats());
  EXPECT_THAT(stats, HasSubstr("\"criticalNodes\":0"));
  EXPECT_THAT(stats, HasSubstr("\"subproblems\":0"));
}

// proto3 `optional` fields are written only when set: an absent lower bound is not a bound of 0.
TEST(MessageJsonTest, UnsetOptionalFieldsStayAbsent) {
  v1::QuantizationResult result;
  EXPECT_THAT(MessageToJson(result), Not(HasSubstr("lowerBound")));
  result.set_lower_bound(0);
  EXPECT_THAT(MessageToJson(result), HasSubstr("\"lowerBound\":0"));
}

TEST(MessageJsonTest, WhatItWritesParsesBack) {
  v1::QuantizationResult result;
  result.add_q(3);
  result.add_q(-1);
  result.set_objective(2.5);
  result.set_termination(v1::TIME_LIMIT);
  result.mutable_stats()->set_lp_solves(7);
  const std::string json = MessageToJson(result);
  EXPECT_THAT(json, HasSubstr("\"termination\":\"TIME_LIMIT\""));
  v1::QuantizationResult parsed;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(json, &parsed).ok());
  EXPECT_EQ(parsed.SerializeAsString(), result.SerializeAsString());
}

}  // namespace
}  // namespace ispq::cli
