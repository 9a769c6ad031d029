// How the client reaches a server: address, transport security and the bearer token, turned
// into a gRPC channel. Shared by the client library and every remote subcommand of `ispq`.
#ifndef ISPQ_CLIENT_SERVER_CONNECTION_H_
#define ISPQ_CLIENT_SERVER_CONNECTION_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "grpcpp/channel.h"

namespace ispq::client {

struct ServerConnection {
  std::string address = "127.0.0.1:50051";  // HOST:PORT, or any gRPC target URI
  // TLS: on if `tls` or any file below is set. Without tls_ca the system's roots verify the
  // server.
  bool tls = false;
  std::string tls_ca_file;    // PEM roots that verify the server's certificate
  std::string tls_cert_file;  // PEM client certificate (mutual TLS), with tls_key_file
  std::string tls_key_file;
  // Sent as `authorization: Bearer <token>` on every Quantizer call if not empty.
  std::string auth_token;

  bool uses_tls() const {
    return tls || !tls_ca_file.empty() || !tls_cert_file.empty() || !tls_key_file.empty();
  }
};

// The channel (connected lazily by gRPC). INVALID_ARGUMENT or NOT_FOUND for unusable TLS files.
absl::StatusOr<std::shared_ptr<grpc::Channel>> OpenChannel(const ServerConnection& connection);

}  // namespace ispq::client

#endif  // ISPQ_CLIENT_SERVER_CONNECTION_H_
