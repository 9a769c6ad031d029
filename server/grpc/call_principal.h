// SPDX-License-Identifier: Apache-2.0
// Who a gRPC call is made by: what the call presents (its `authorization` metadata, the subject
// of its verified client certificate) given to the Authenticator (server/auth/authenticator.h).
#ifndef ISPQ_SERVER_GRPC_CALL_PRINCIPAL_H_
#define ISPQ_SERVER_GRPC_CALL_PRINCIPAL_H_

#include "absl/status/statusor.h"
#include "grpcpp/server_context.h"
#include "server/auth/authenticator.h"
#include "server/auth/principal.h"

namespace ispq::server {

// The caller of `context`'s call, or UNAUTHENTICATED without saying which part was wrong.
absl::StatusOr<Principal> CallPrincipal(const Authenticator& authenticator,
                                        const grpc::ServerContextBase& context);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_CALL_PRINCIPAL_H_
