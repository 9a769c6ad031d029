// SPDX-License-Identifier: Apache-2.0
#include "server/http/http_router.h"

#include <utility>

namespace ispq::server::http {
namespace {

constexpr absl::string_view kIdSegment = "{id}";

// Whether `path` matches `pattern`, and what its {id} stands for.
bool Matches(absl::string_view pattern, absl::string_view path, std::string* id) {
  const size_t at = pattern.find(kIdSegment);
  if (at == absl::string_view::npos) return pattern == path;
  const absl::string_view prefix = pattern.substr(0, at);
  const absl::string_view suffix = pattern.substr(at + kIdSegment.size());
  if (path.size() <= prefix.size() + suffix.size() || path.substr(0, prefix.size()) != prefix ||
      path.substr(path.size() - suffix.size()) != suffix) {
    return false;
  }
  const absl::string_view matched =
      path.substr(prefix.size(), path.size() - prefix.size() - suffix.size());
  if (matched.find_first_of("/:") != absl::string_view::npos) return false;
  *id = std::string(matched);
  return true;
}

}  // namespace

void Router::Add(Route route) { routes_.push_back(std::move(route)); }

const Route* Router::Match(absl::string_view method, absl::string_view path,
                           std::string* id) const {
  if (method == "HEAD") method = "GET";
  for (const Route& route : routes_) {
    if (route.method == method && Matches(route.pattern, path, id)) return &route;
  }
  return nullptr;
}

}  // namespace ispq::server::http
