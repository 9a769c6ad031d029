// SPDX-License-Identifier: Apache-2.0
// The transport security of the listening port: plaintext by default (loopback), TLS with the
// server's certificate, or mutual TLS that requires and verifies client certificates.
#ifndef ISPQ_SERVER_SERVER_CREDENTIALS_H_
#define ISPQ_SERVER_SERVER_CREDENTIALS_H_

#include <memory>

#include "absl/status/statusor.h"
#include "grpcpp/security/server_credentials.h"
#include "server/server_config.h"

namespace ispq::server {

// Reads the PEM files; NOT_FOUND or INVALID_ARGUMENT naming the file that cannot be used.
absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(const TlsFiles& tls);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_SERVER_CREDENTIALS_H_
