#include "client/server_connection.h"

#include "absl/status/status.h"
#include "core/read_file.h"
#include "grpcpp/create_channel.h"
#include "grpcpp/security/credentials.h"
#include "grpcpp/support/channel_arguments.h"

namespace ispq::client {
namespace {

constexpr size_t kMaxPemBytes = 1 << 20;
// Results and intermediate quantizations carry one integer per arc; leave room for big meshes.
constexpr int kMaxReceiveMessageBytes = 256 << 20;

absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> Credentials(
    const ServerConnection& connection) {
  if (!connection.uses_tls()) return grpc::InsecureChannelCredentials();
  if (connection.tls_cert_file.empty() != connection.tls_key_file.empty()) {
    return absl::InvalidArgumentError("a client certificate needs both --tls_cert and --tls_key");
  }
  grpc::SslCredentialsOptions options;
  if (!connection.tls_ca_file.empty()) {
    absl::StatusOr<std::string> roots = ReadFileToString(connection.tls_ca_file, kMaxPemBytes);
    if (!roots.ok()) return roots.status();
    options.pem_root_certs = *roots;
  }
  if (!connection.tls_cert_file.empty()) {
    absl::StatusOr<std::string> cert = ReadFileToString(connection.tls_cert_file, kMaxPemBytes);
    if (!cert.ok()) return cert.status();
    absl::StatusOr<std::string> key = ReadFileToString(connection.tls_key_file, kMaxPemBytes);
    if (!key.ok()) return key.status();
    options.pem_cert_chain = *cert;
    options.pem_private_key = *key;
  }
  return grpc::SslCredentials(options);
}

}  // namespace

absl::StatusOr<std::shared_ptr<grpc::Channel>> OpenChannel(const ServerConnection& connection) {
  if (connection.address.empty()) return absl::InvalidArgumentError("no server address given");
  absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> credentials = Credentials(connection);
  if (!credentials.ok()) return credentials.status();
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(kMaxReceiveMessageBytes);
  arguments.SetMaxSendMessageSize(-1);  // the server enforces its own limit
  return grpc::CreateCustomChannel(connection.address, *credentials, arguments);
}

}  // namespace ispq::client
