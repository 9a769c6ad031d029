// SPDX-License-Identifier: Apache-2.0
// The bearer tokens a server accepts and the principal each one stands for, read from
// --auth_tokens_file: one "PRINCIPAL TOKEN" pair per line, blank lines and lines starting with
// '#' ignored, e.g.
//
//   # principal  token
//   alice        8f1c0f4e0b1d4f7e9a6b
//   pipeline     3a9e55d1c2b04c83b1f0
//
// The single-token flags (--auth_token, --auth_token_file) are one principal named "default".
#ifndef ISPQ_SERVER_AUTH_PRINCIPAL_TOKENS_H_
#define ISPQ_SERVER_AUTH_PRINCIPAL_TOKENS_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"

namespace ispq::server {

inline constexpr char kSingleTokenPrincipal[] = "default";

struct PrincipalToken {
  std::string principal;
  std::string token;
};

// INVALID_ARGUMENT naming the line for a malformed line, a duplicate token or an empty file.
absl::StatusOr<std::vector<PrincipalToken>> ParsePrincipalTokens(absl::string_view contents);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_AUTH_PRINCIPAL_TOKENS_H_
