// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/call_principal.h"

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "grpc/grpc_security_constants.h"
#include "grpcpp/security/auth_context.h"

namespace ispq::server {
namespace {

std::string_view Authorization(const grpc::ServerContextBase& context) {
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("authorization");
  if (it == metadata.end()) return std::string_view();
  return std::string_view(it->second.data(), it->second.size());
}

// The subject of the call's verified client certificate; empty if it has none.
std::string CertificateSubject(const grpc::ServerContextBase& context) {
  const std::shared_ptr<const grpc::AuthContext> auth = context.auth_context();
  if (auth == nullptr || !auth->IsPeerAuthenticated()) return std::string();
  const std::vector<grpc::string_ref> subjects =
      auth->FindPropertyValues(GRPC_X509_SUBJECT_PROPERTY_NAME);
  if (subjects.empty()) return std::string();
  return std::string(subjects.front().data(), subjects.front().size());
}

}  // namespace

absl::StatusOr<Principal> CallPrincipal(const Authenticator& authenticator,
                                        const grpc::ServerContextBase& context) {
  // The auth context is looked at only where certificates name the principals, as it costs
  // an allocation per call.
  const std::string subject =
      authenticator.NamesByCertificate() ? CertificateSubject(context) : std::string();
  return authenticator.Authenticate(Authorization(context), subject);
}

}  // namespace ispq::server
