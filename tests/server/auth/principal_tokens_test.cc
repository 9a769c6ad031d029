// SPDX-License-Identifier: Apache-2.0
#include "server/auth/principal_tokens.h"

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;

TEST(PrincipalTokensTest, ReadsPrincipalTokenLinesSkippingCommentsAndBlanks) {
  const absl::StatusOr<std::vector<PrincipalToken>> tokens =
      ParsePrincipalTokens("# principal token\n\nalice  a-secret\n\t bob\tb-secret \n");
  ASSERT_TRUE(tokens.ok()) << tokens.status();
  ASSERT_EQ(tokens->size(), 2u);
  EXPECT_EQ((*tokens)[0].principal, "alice");
  EXPECT_EQ((*tokens)[0].token, "a-secret");
  EXPECT_EQ((*tokens)[1].principal, "bob");
  EXPECT_EQ((*tokens)[1].token, "b-secret");
}

TEST(PrincipalTokensTest, NamesTheLineOfAMistake) {
  EXPECT_THAT(std::string(ParsePrincipalTokens("alice a\nbob\n").status().message()),
              HasSubstr("line 2: expected 'PRINCIPAL TOKEN'"));
  EXPECT_THAT(std::string(ParsePrincipalTokens("alice a b\n").status().message()),
              HasSubstr("line 1"));
  EXPECT_THAT(std::string(ParsePrincipalTokens("alice t\n# x\nbob t\n").status().message()),
              HasSubstr("line 3: the token is already used"));
  EXPECT_EQ(ParsePrincipalTokens("# nothing\n").status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace ispq::server
