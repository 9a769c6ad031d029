// SPDX-License-Identifier: Apache-2.0
#include "server/logging/log_value.h"

#include "absl/strings/str_format.h"

namespace ispq::server {
namespace {

constexpr size_t kMaxLoggedBytes = 200;

}  // namespace

std::string QuotedLogValue(const std::string& value) {
  std::string quoted = "\"";
  for (size_t i = 0; i < value.size() && i < kMaxLoggedBytes; ++i) {
    const unsigned char c = static_cast<unsigned char>(value[i]);
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      quoted += absl::StrFormat("\\x%02x", c);
    } else {
      quoted += static_cast<char>(c);
    }
  }
  if (value.size() > kMaxLoggedBytes) quoted += "...";
  quoted += '"';
  return quoted;
}

}  // namespace ispq::server
