// SPDX-License-Identifier: Apache-2.0
#include "server/model/resource_names.h"

#include <cstdint>

#include "absl/random/random.h"
#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace ispq::server {
namespace {

constexpr size_t kMaxIdLength = 63;
constexpr size_t kMaxQuotedLength = 80;

bool IsWellFormedId(const std::string& id) {
  if (id.empty() || id.size() > kMaxIdLength) return false;
  for (char c : id) {
    const bool allowed = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-';
    if (!allowed) return false;
  }
  return true;
}

// Names come from clients; a megabyte-long or binary one must not end up whole in a message.
std::string Quote(const std::string& text) {
  std::string shown = text.substr(0, kMaxQuotedLength);
  for (char& c : shown) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  }
  if (text.size() > kMaxQuotedLength) absl::StrAppend(&shown, "... (", text.size(), " bytes)");
  return absl::StrCat("'", shown, "'");
}

}  // namespace

std::string NewResourceId() {
  // absl::BitGen is not thread-safe; each thread seeds its own from the OS.
  thread_local absl::BitGen generator;
  return absl::StrFormat("%016x", absl::Uniform<uint64_t>(generator));
}

std::string ResourceName(const char* collection, const std::string& id) {
  return absl::StrCat(collection, "/", id);
}

absl::StatusOr<std::string> ParseResourceName(const char* collection, const std::string& name) {
  const std::string prefix = absl::StrCat(collection, "/");
  if (name.rfind(prefix, 0) == 0) {
    std::string id = name.substr(prefix.size());
    if (IsWellFormedId(id)) return id;
  }
  return absl::InvalidArgumentError(
      absl::StrCat("resource name ", Quote(name), " is not of the form ", collection,
                   "/{id} (id: 1 to ", kMaxIdLength, " characters from a-z, 0-9 and '-')"));
}

}  // namespace ispq::server
