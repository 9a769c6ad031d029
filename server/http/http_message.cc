// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_message.h"

namespace ispq::server::http {
namespace {

const std::string* Find(const HttpFields& fields, absl::string_view name) {
  for (const auto& [key, value] : fields) {
    if (key == name) return &value;
  }
  return nullptr;
}

}  // namespace

absl::string_view HttpRequest::Header(absl::string_view name) const {
  const std::string* value = Find(headers, name);
  return value == nullptr ? absl::string_view() : absl::string_view(*value);
}

bool HttpRequest::HasParam(absl::string_view name) const { return Find(query, name) != nullptr; }

absl::string_view HttpRequest::Param(absl::string_view name) const {
  const std::string* value = Find(query, name);
  return value == nullptr ? absl::string_view() : absl::string_view(*value);
}

void HttpRequest::ReleaseBody() {
  // A swap, not an assignment: assigning an empty string keeps the body's buffer (libstdc++
  // moves a short string into the existing allocation), which would then outlive its
  // reservation unaccounted.
  std::string().swap(body);
  body_memory.clear();
}

}  // namespace ispq::server::http
