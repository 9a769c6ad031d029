// SPDX-License-Identifier: Apache-2.0
// Authentication of Quantizer calls: the principal (server/auth/principal.h) a call is made by,
// from what the call presents, whichever transport brought it (gRPC's calls present theirs in
// server/grpc/call_principal.h, the HTTP side's in server/http/).
//
//   * Bearer tokens (--auth_tokens_file, or one token from --auth_token/--auth_token_file): a call
//     must carry `authorization: Bearer <token>`, and the token's principal is the caller.
//   * Client certificates (mutual TLS, --tls_client_ca) without tokens: the caller is the
//     subject of its verified certificate, e.g. "CN=alice,O=Example" (RFC 2253 form). With
//     tokens, the certificate only secures the connection and the token names the principal.
//   * Neither: every caller is the anonymous principal "".
// Principals listed in --admin_principals are admins. Health checking and reflection are not
// Quantizer calls and stay open (orchestrators probe them without credentials).
#ifndef ISPQ_SERVER_AUTH_AUTHENTICATOR_H_
#define ISPQ_SERVER_AUTH_AUTHENTICATOR_H_

#include <string>
#include <string_view>
#include <vector>

#include "absl/container/flat_hash_set.h"
#include "absl/status/statusor.h"
#include "server/auth/principal.h"
#include "server/auth/principal_tokens.h"

namespace ispq::server {

struct AuthenticationConfig {
  std::vector<PrincipalToken> tokens;  // empty: no bearer tokens
  bool client_certificates = false;    // mutual TLS: verified certificates name principals
  std::vector<std::string> admin_principals;
};

class Authenticator {
 public:
  explicit Authenticator(AuthenticationConfig config);

  // The caller of a call that presents `authorization` (its `authorization` metadata, empty if
  // absent) over a connection whose verified client certificate names `certificate_subject`
  // (RFC 2253 form; empty: no verified certificate, or one without a subject), or
  // UNAUTHENTICATED without saying which part was wrong.
  absl::StatusOr<Principal> Authenticate(std::string_view authorization,
                                         std::string_view certificate_subject) const;
  // Whether certificates name the principals (mutual TLS without tokens): only then does
  // Authenticate look at the certificate's subject.
  bool NamesByCertificate() const { return config_.tokens.empty() && config_.client_certificates; }
  // The same for a plaintext HTTP request (server/http/) with this `Authorization` header value
  // (empty if absent). It has no client certificate: where certificates name the principals
  // and there are no tokens, it is UNAUTHENTICATED, so plaintext HTTP never bypasses mutual TLS.
  absl::StatusOr<Principal> AuthenticateHttp(std::string_view authorization) const;

 private:
  absl::StatusOr<std::string> PrincipalName(std::string_view authorization,
                                            std::string_view certificate_subject) const;
  absl::StatusOr<std::string> TokenPrincipal(std::string_view authorization) const;
  Principal PrincipalNamed(std::string name) const;

  const AuthenticationConfig config_;
  const absl::flat_hash_set<std::string> admins_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_AUTH_AUTHENTICATOR_H_
