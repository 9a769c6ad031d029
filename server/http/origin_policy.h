// SPDX-License-Identifier: Apache-2.0
// Which Host and Origin a request may come with, against DNS rebinding and cross-site request
// forgery. A page on any site can make a browser send a "simple" POST (a form, or fetch with
// Content-Type text/plain) to this server and, after rebinding its own name to this server's
// address, read what this server answers under that name. So:
//
//   * The Host header must be one this server is known by (--http_allowed_hosts; by default the
//     listen address's host, localhost, 127.0.0.1 and [::1] at the bound port), else 421
//     (Misdirected Request: the name is not this server's) with body status PERMISSION_DENIED.
//     /healthz, /readyz and /metrics are exempt: orchestrators probe them by IP address and they
//     hold counts only.
//   * A POST without credentials (no Authorization header, which no cross-site page can add
//     without this server's consent, and it gives none) must be a request a cross-site page cannot
//     send without that consent either: Content-Type application/json (server/http/
//     request_framing.h) and, when the browser says where it comes from (Origin), this server's
//     own origin, http:// and the Host; else 403.
#ifndef ISPQ_SERVER_HTTP_ORIGIN_POLICY_H_
#define ISPQ_SERVER_HTTP_ORIGIN_POLICY_H_

#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "server/http/http_message.h"

namespace ispq::server::http {

class OriginPolicy {
 public:
  // `allowed_hosts` as --http_allowed_hosts takes them (ValidateAllowedHost); empty: the
  // defaults for `listen_host` (as --http_listen has it, without brackets) and `port`.
  OriginPolicy(const std::vector<std::string>& allowed_hosts, absl::string_view listen_host,
               int port);

  // 421 unless the Host header is an allowed one; 400 if there are several.
  absl::Status CheckHost(const HttpRequest& request) const;
  // 403 for a POST without credentials whose Origin, if it has one, is another site's.
  absl::Status CheckOrigin(const HttpRequest& request) const;

  const std::vector<std::string>& allowed_hosts() const { return allowed_; }

 private:
  bool Allowed(absl::string_view host) const;

  std::vector<std::string> allowed_;  // lower case; "name" (any port), "name:port" or "*"
};

// INVALID_ARGUMENT unless `entry` is "*", a host name or address, or one with ":port"
// (IPv6 addresses in brackets: "[::1]:8080").
absl::Status ValidateAllowedHost(absl::string_view entry);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_ORIGIN_POLICY_H_
