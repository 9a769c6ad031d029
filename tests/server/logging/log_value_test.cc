// SPDX-License-Identifier: Apache-2.0
// QuotedLogValue (server/logging/log_value.h): a client-controlled string in a structured log line
// stays one quoted value, however it is made: it cannot end the quotes, start a new line or
// fill the log.
#include "server/logging/log_value.h"

#include <string>

#include "absl/strings/str_cat.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

TEST(LogValueTest, PlainTextIsQuotedAsIs) {
  EXPECT_EQ(QuotedLogValue(""), "\"\"");
  EXPECT_EQ(QuotedLogValue("s07c notch.tmesh"), "\"s07c notch.tmesh\"");
  // Bytes above ASCII (UTF-8 names) are not control characters and pass through.
  EXPECT_EQ(QuotedLogValue("w\xc3\xbcrfel"), "\"w\xc3\xbcrfel\"");
}

// A value that closes the quotes and adds a field of its own must stay inside them.
TEST(LogValueTest, QuotesAndBackslashesAreEscaped) {
  EXPECT_EQ(QuotedLogValue("a\" state=SUCCEEDED x=\""), R"("a\" state=SUCCEEDED x=\"")");
  EXPECT_EQ(QuotedLogValue("C:\\mesh\\"), R"("C:\\mesh\\")");
  // A trailing backslash must not escape the closing quote.
  EXPECT_EQ(QuotedLogValue("\\").back(), '"');
  EXPECT_EQ(QuotedLogValue("\\"), R"("\\")");
}

// A newline would forge a whole log line; every control character, DEL included, is shown as
// \xNN instead.
TEST(LogValueTest, ControlCharactersAreHexEscaped) {
  EXPECT_EQ(QuotedLogValue("a\nts=2026 level=error forged"),
            R"("a\x0ats=2026 level=error forged")");
  EXPECT_EQ(QuotedLogValue("\r\t\x1b[31m"), R"("\x0d\x09\x1b[31m")");
  EXPECT_EQ(QuotedLogValue(std::string("nul\0del\x7f", 8)), R"("nul\x00del\x7f")");
}

TEST(LogValueTest, LongValuesAreCutAfterTwoHundredBytes) {
  const std::string at_limit(200, 'x');
  EXPECT_EQ(QuotedLogValue(at_limit), absl::StrCat("\"", at_limit, "\""));
  EXPECT_EQ(QuotedLogValue(at_limit + "TAIL"), absl::StrCat("\"", at_limit, "...\""));
  // The limit counts input bytes: escaping does not let more of a long value through, and the cut
  // value is still closed by its quote.
  std::string escaped;
  for (int i = 0; i < 200; ++i) escaped += "\\x0a";
  EXPECT_EQ(QuotedLogValue(std::string(10000, '\n')), absl::StrCat("\"", escaped, "...\""));
}

}  // namespace
}  // namespace ispq::server
