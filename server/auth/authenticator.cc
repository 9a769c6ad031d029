// SPDX-License-Identifier: Apache-2.0
#include "server/auth/authenticator.h"

#include <string_view>
#include <utility>

#include "absl/status/status.h"

namespace ispq::server {
namespace {

constexpr std::string_view kBearerPrefix = "Bearer ";

// Compares in time that depends on the lengths only, so that a token cannot be guessed one byte
// at a time from response times.
bool ConstantTimeEquals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  unsigned char difference = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    difference |= static_cast<unsigned char>(a[i] ^ b[i]);
  }
  return difference == 0;
}

}  // namespace

Authenticator::Authenticator(AuthenticationConfig config)
    : config_(std::move(config)),
      admins_(config_.admin_principals.begin(), config_.admin_principals.end()) {}

absl::StatusOr<Principal> Authenticator::Authenticate(std::string_view authorization,
                                                      std::string_view certificate_subject) const {
  absl::StatusOr<std::string> name = PrincipalName(authorization, certificate_subject);
  if (!name.ok()) return name.status();
  return PrincipalNamed(*std::move(name));
}

absl::StatusOr<Principal> Authenticator::AuthenticateHttp(std::string_view authorization) const {
  if (!config_.tokens.empty()) {
    absl::StatusOr<std::string> name = TokenPrincipal(authorization);
    if (!name.ok()) return name.status();
    return PrincipalNamed(*std::move(name));
  }
  if (config_.client_certificates) {
    return absl::UnauthenticatedError(
        "this server names its principals by client certificate, which plaintext HTTP cannot "
        "carry: use gRPC with mutual TLS");
  }
  return PrincipalNamed(std::string());
}

Principal Authenticator::PrincipalNamed(std::string name) const {
  Principal principal;
  principal.admin = admins_.contains(name);
  principal.name = std::move(name);
  return principal;
}

absl::StatusOr<std::string> Authenticator::TokenPrincipal(std::string_view authorization) const {
  if (authorization.substr(0, kBearerPrefix.size()) == kBearerPrefix) {
    const std::string_view presented = authorization.substr(kBearerPrefix.size());
    // Every token is compared, so that the time does not tell which one came close.
    const PrincipalToken* match = nullptr;
    for (const PrincipalToken& entry : config_.tokens) {
      if (ConstantTimeEquals(presented, entry.token)) match = &entry;
    }
    if (match != nullptr) return match->principal;
  }
  return absl::UnauthenticatedError(
      "missing or wrong bearer token (metadata 'authorization: Bearer <token>')");
}

absl::StatusOr<std::string> Authenticator::PrincipalName(
    std::string_view authorization, std::string_view certificate_subject) const {
  if (!config_.tokens.empty()) return TokenPrincipal(authorization);
  if (config_.client_certificates) {
    if (!certificate_subject.empty()) return std::string(certificate_subject);
    return absl::UnauthenticatedError("the client certificate names no subject");
  }
  return std::string();
}

}  // namespace ispq::server
