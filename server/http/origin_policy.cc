// SPDX-License-Identifier: Apache-2.0
#include "server/http/origin_policy.h"

#include <utility>

#include "absl/algorithm/container.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "server/http/http_status.h"

namespace ispq::server::http {
namespace {

constexpr int kMisdirectedRequest = 421;

// "name" and "port" of "name:port" ("[v6]:port" keeps its brackets); port empty if absent.
std::pair<absl::string_view, absl::string_view> SplitPort(absl::string_view host) {
  const size_t colon = host.rfind(':');
  const size_t bracket = host.rfind(']');
  if (colon == absl::string_view::npos || (bracket != absl::string_view::npos && colon < bracket)) {
    return {host, ""};
  }
  return {host.substr(0, colon), host.substr(colon + 1)};
}

// `host` in lower case with an explicit port (80 when absent, as browsers leave it out).
std::string WithPort(absl::string_view host) {
  std::string lower = absl::AsciiStrToLower(host);
  if (SplitPort(lower).second.empty()) absl::StrAppend(&lower, ":80");
  return lower;
}

bool ValidName(absl::string_view name) {
  if (name.size() > 2 && name.front() == '[' && name.back() == ']') {
    return absl::c_all_of(name.substr(1, name.size() - 2),
                          [](char c) { return absl::ascii_isxdigit(c) || c == ':' || c == '.'; });
  }
  return !name.empty() && absl::c_all_of(name, [](char c) {
    return absl::ascii_isalnum(c) || c == '-' || c == '.' || c == '_';
  });
}

std::string Bracketed(absl::string_view host) {
  if (host.find(':') != absl::string_view::npos) return absl::StrCat("[", host, "]");
  return std::string(host);
}

absl::Status InvalidHostEntry(absl::string_view entry) {
  return absl::InvalidArgumentError(absl::StrCat(
      "--http_allowed_hosts entry \"", entry,
      "\" is not *, a host name or address, or one with :PORT (e.g. ispq.example.com:8080)"));
}

}  // namespace

OriginPolicy::OriginPolicy(const std::vector<std::string>& allowed_hosts,
                           absl::string_view listen_host, int port) {
  if (!allowed_hosts.empty()) {
    for (const std::string& host : allowed_hosts) allowed_.push_back(absl::AsciiStrToLower(host));
    return;
  }
  for (absl::string_view host : {Bracketed(listen_host), std::string("localhost"),
                                 std::string("127.0.0.1"), std::string("[::1]")}) {
    allowed_.push_back(absl::StrCat(absl::AsciiStrToLower(host), ":", port));
  }
}

bool OriginPolicy::Allowed(absl::string_view host) const {
  const std::string requested = WithPort(host);
  const absl::string_view name = SplitPort(requested).first;
  for (const std::string& entry : allowed_) {
    if (entry == "*" || entry == requested || entry == name) return true;
  }
  return false;
}

absl::Status OriginPolicy::CheckHost(const HttpRequest& request) const {
  const absl::string_view host = request.Header("host");
  const auto hosts =
      absl::c_count_if(request.headers, [](const auto& h) { return h.first == "host"; });
  if (hosts > 1) return absl::InvalidArgumentError("Host given more than once");
  if (!host.empty() && Allowed(host)) return absl::OkStatus();
  return WithHttpStatus(absl::PermissionDeniedError(absl::StrCat(
                            "Host ", host.empty() ? "missing" : std::string(host.substr(0, 100)),
                            " is not a name of this server (--http_allowed_hosts)")),
                        kMisdirectedRequest);
}

absl::Status OriginPolicy::CheckOrigin(const HttpRequest& request) const {
  if (request.method != "POST" || !request.Header("authorization").empty()) {
    return absl::OkStatus();
  }
  const absl::string_view origin = request.Header("origin");
  if (origin.empty()) return absl::OkStatus();
  const std::string lower = absl::AsciiStrToLower(origin);
  if (absl::StartsWith(lower, "http://") &&
      WithPort(lower.substr(7)) == WithPort(request.Header("host"))) {
    return absl::OkStatus();
  }
  return absl::PermissionDeniedError(
      absl::StrCat("a POST from the page at ", origin.substr(0, 100),
                   " without credentials: only this server's own pages may send one"));
}

absl::Status ValidateAllowedHost(absl::string_view entry) {
  if (entry == "*") return absl::OkStatus();
  if (entry.empty() || entry.back() == ':') return InvalidHostEntry(entry);
  const auto [name, port] = SplitPort(entry);
  int number = 0;
  const bool port_ok =
      port.empty() || (absl::SimpleAtoi(port, &number) && number > 0 && number <= 65535 &&
                       absl::c_all_of(port, absl::ascii_isdigit));
  if (ValidName(name) && port_ok) return absl::OkStatus();
  return InvalidHostEntry(entry);
}

}  // namespace ispq::server::http
