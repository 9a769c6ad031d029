// SPDX-License-Identifier: Apache-2.0
// CallPrincipal (server/grpc/call_principal.h): who a gRPC call is made by, read from real calls
// to a test method on an in-process gRPC server that answers with the caller's name: the
// `authorization` metadata names the caller with tokens, everyone is anonymous without any
// authentication, and where certificates name the principals a call without a verified
// certificate is UNAUTHENTICATED, whatever else it presents. (Calls over mutual TLS, whose
// certificate subject is the principal, are tested with real certificates in
// tests/integration/ownership_test.cc.)
#include "server/grpc/call_principal.h"

#include <memory>
#include <string>

#include "grpcpp/grpcpp.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"
#include "server/grpc/grpc_status.h"

namespace ispq::server {
namespace {

// GetJob answers with the caller's name as the job's owner.
class WhoIsCalling : public v1::Quantizer::WithCallbackMethod_GetJob<v1::Quantizer::Service> {
 public:
  explicit WhoIsCalling(const Authenticator& authenticator) : authenticator_(authenticator) {}

  grpc::ServerUnaryReactor* GetJob(grpc::CallbackServerContext* context, const v1::GetJobRequest*,
                                   v1::Job* response) override {
    grpc::ServerUnaryReactor* reactor = context->DefaultReactor();
    const absl::StatusOr<Principal> principal = CallPrincipal(authenticator_, *context);
    if (principal.ok()) response->set_owner(principal->name);
    reactor->Finish(ToGrpcStatus(principal.status()));
    return reactor;
  }

 private:
  const Authenticator& authenticator_;
};

// The caller's name as the server sees it, presenting `authorization` (nothing if empty).
absl::StatusOr<std::string> Caller(const AuthenticationConfig& config,
                                   const std::string& authorization) {
  const Authenticator authenticator(config);
  WhoIsCalling service(authenticator);
  grpc::ServerBuilder builder;
  builder.RegisterService(&service);
  const std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  const std::unique_ptr<v1::Quantizer::Stub> stub =
      v1::Quantizer::NewStub(server->InProcessChannel(grpc::ChannelArguments()));
  grpc::ClientContext context;
  if (!authorization.empty()) context.AddMetadata("authorization", authorization);
  v1::Job job;
  const grpc::Status status = stub->GetJob(&context, v1::GetJobRequest(), &job);
  server->Shutdown();
  if (!status.ok()) {
    return absl::Status(static_cast<absl::StatusCode>(status.error_code()), status.error_message());
  }
  return job.owner();
}

AuthenticationConfig Tokens() {
  AuthenticationConfig config;
  config.tokens = {{"alice", "token-of-alice"}, {"bob", "token-of-bob"}};
  return config;
}

TEST(CallPrincipalTest, TheAuthorizationMetadataNamesTheCaller) {
  EXPECT_EQ(Caller(Tokens(), "Bearer token-of-alice").value_or("?"), "alice");
  EXPECT_EQ(Caller(Tokens(), "Bearer token-of-bob").value_or("?"), "bob");
  for (const char* wrong : {"", "Bearer token-of-mallory", "token-of-alice"}) {
    EXPECT_EQ(Caller(Tokens(), wrong).status().code(), absl::StatusCode::kUnauthenticated)
        << "'" << wrong << "'";
  }
}

TEST(CallPrincipalTest, WithoutAuthenticationEveryCallerIsAnonymous) {
  EXPECT_EQ(Caller(AuthenticationConfig(), "").value_or("?"), "");
  EXPECT_EQ(Caller(AuthenticationConfig(), "Bearer token-of-alice").value_or("?"), "");
}

// A plaintext call has no verified certificate: where certificates name the principals, it is
// no one, and a bearer header does not stand in for the certificate.
TEST(CallPrincipalTest, WhereCertificatesNameCallersACallWithoutOneIsUnauthenticated) {
  AuthenticationConfig certificates;
  certificates.client_certificates = true;
  EXPECT_EQ(Caller(certificates, "").status().code(), absl::StatusCode::kUnauthenticated);
  EXPECT_EQ(Caller(certificates, "Bearer token-of-alice").status().code(),
            absl::StatusCode::kUnauthenticated);
  // With tokens as well, the certificate only secures the connection; the token names.
  AuthenticationConfig both = Tokens();
  both.client_certificates = true;
  EXPECT_EQ(Caller(both, "Bearer token-of-alice").value_or("?"), "alice");
}

}  // namespace
}  // namespace ispq::server
