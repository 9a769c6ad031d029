// SPDX-License-Identifier: Apache-2.0
#include "server/http/json_guard.h"

#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

std::string Nested(int depth) { return std::string(depth, '[') + std::string(depth, ']'); }

TEST(JsonGuardTest, TakesTheApisRequests) {
  EXPECT_TRUE(CheckJsonBody(R"({"mesh": {"arcs": [{"length": 2}, {"length": 3}]},
                                "options": {"scaling": {"levelPercent": 25}},
                                "requestId": "r-\u00e9\"}"})")
                  .ok());
  EXPECT_TRUE(CheckJsonBody("{\"name\": \"caf\xc3\xa9 \xf0\x9f\x99\x82\"}").ok());
  // Keys repeated in different objects, and strings that look like keys, are fine.
  EXPECT_TRUE(CheckJsonBody(R"({"a": {"a": 1}, "b": [{"a": 1}, {"a": 2}], "c": "a"})").ok());
  EXPECT_TRUE(CheckJsonBody(R"(["a", "a", {"x": "y", "y": "x"}])").ok());
}

TEST(JsonGuardTest, BoundsTheNestingDepth) {
  EXPECT_TRUE(CheckJsonBody(Nested(kMaxJsonDepth)).ok());
  const absl::Status deep = CheckJsonBody(Nested(kMaxJsonDepth + 1));
  EXPECT_EQ(deep.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(deep.message(), HasSubstr("deeper than 64 levels"));
  EXPECT_FALSE(CheckJsonBody("{\"a\":" + std::string(1000000, '[')).ok());
  // Brackets inside strings do not count.
  EXPECT_TRUE(CheckJsonBody("{\"a\": \"" + std::string(1000, '[') + "\"}").ok());
}

TEST(JsonGuardTest, RefusesNulBomAndInvalidUtf8) {
  EXPECT_THAT(CheckJsonBody(std::string("{\"a\": \"x\0y\"}", 12)).message(), HasSubstr("NUL"));
  EXPECT_THAT(CheckJsonBody(std::string("{}\0", 3)).message(), HasSubstr("NUL"));
  EXPECT_THAT(CheckJsonBody("\xEF\xBB\xBF{}").message(), HasSubstr("byte order mark"));
  for (const char* invalid :
       {"{\"a\": \"\xff\"}", "{\"a\": \"\xc0\xaf\"}", "{\"a\": \"\xed\xa0\x80\"}",
        "{\"a\": \"\xf4\x90\x80\x80\"}", "{\"a\": \"\xe2\x82\"}"}) {
    EXPECT_THAT(CheckJsonBody(invalid).message(), HasSubstr("not valid UTF-8")) << invalid;
  }
}

TEST(JsonGuardTest, RefusesRepeatedKeysAsTheParserMatchesThem) {
  EXPECT_THAT(CheckJsonBody(R"({"mesh": {}, "mesh": {}})").message(),
              HasSubstr("repeats the key \"mesh\""));
  EXPECT_FALSE(CheckJsonBody(R"({"a": {"b": 1, "c": 2, "b": 3}})").ok());
  // The proto name and the JSON name of one field, and escaped spellings, are the same key.
  EXPECT_FALSE(CheckJsonBody(R"({"stored_mesh": "a", "storedMesh": "b"})").ok());
  EXPECT_FALSE(CheckJsonBody(R"({"mesh": 1, "m\u0065sh": 2})").ok());
  // Objects with many keys too.
  std::string many = "{";
  for (int i = 0; i < 1000; ++i) many += "\"k" + std::to_string(i) + "\": 1, ";
  EXPECT_TRUE(CheckJsonBody(many + "\"last\": 1}").ok());
  EXPECT_FALSE(CheckJsonBody(many + "\"k500\": 1}").ok());
}

TEST(JsonGuardTest, LeavesMalformedJsonToTheParser) {
  EXPECT_TRUE(CheckJsonBody("{\"mesh\": [1, 2").ok());
  EXPECT_TRUE(CheckJsonBody("]]]").ok());
  EXPECT_TRUE(CheckJsonBody("{\"a").ok());
  EXPECT_TRUE(CheckJsonBody("").ok());
}

}  // namespace
}  // namespace ispq::server::http
