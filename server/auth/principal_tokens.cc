// SPDX-License-Identifier: Apache-2.0
#include "server/auth/principal_tokens.h"

#include "absl/container/flat_hash_set.h"
#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace ispq::server {

absl::StatusOr<std::vector<PrincipalToken>> ParsePrincipalTokens(absl::string_view contents) {
  std::vector<PrincipalToken> entries;
  absl::flat_hash_set<std::string> tokens;
  int line_number = 0;
  for (absl::string_view line : absl::StrSplit(contents, '\n')) {
    ++line_number;
    line = absl::StripAsciiWhitespace(line);
    if (line.empty() || line.front() == '#') continue;
    const std::vector<std::string> fields =
        absl::StrSplit(line, absl::ByAnyChar(" \t"), absl::SkipEmpty());
    if (fields.size() != 2) {
      return absl::InvalidArgumentError(
          absl::StrCat("line ", line_number, ": expected 'PRINCIPAL TOKEN'"));
    }
    if (!tokens.insert(fields[1]).second) {
      return absl::InvalidArgumentError(
          absl::StrCat("line ", line_number, ": the token is already used on an earlier line"));
    }
    entries.push_back({fields[0], fields[1]});
  }
  if (entries.empty()) return absl::InvalidArgumentError("no 'PRINCIPAL TOKEN' line");
  return entries;
}

}  // namespace ispq::server
