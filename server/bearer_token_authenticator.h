// The optional shared-secret check of the Quantizer service: every call must carry the metadata
// `authorization: Bearer <token>`. Off when the token is empty (the loopback default).
//
// It guards the ispq.v1.Quantizer methods only; health checking and reflection stay open so
// that orchestrators (Kubernetes gRPC probes) and grpcurl work without the secret. The token is
// a bearer secret: use it with TLS whenever the server is reachable beyond the host.
#ifndef ISPQ_SERVER_BEARER_TOKEN_AUTHENTICATOR_H_
#define ISPQ_SERVER_BEARER_TOKEN_AUTHENTICATOR_H_

#include <string>

#include "grpcpp/server_context.h"

namespace ispq::server {

class BearerTokenAuthenticator {
 public:
  explicit BearerTokenAuthenticator(std::string token);

  bool enabled() const { return !token_.empty(); }
  // OK, or UNAUTHENTICATED without saying which part was wrong.
  grpc::Status Check(const grpc::ServerContextBase& context) const;

 private:
  const std::string token_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_BEARER_TOKEN_AUTHENTICATOR_H_
