// SPDX-License-Identifier: Apache-2.0
#include "client/server_connection.h"

#include "absl/status/status.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/string_view.h"
#include "absl/strings/strip.h"
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

// Retries of the idempotent unary methods on UNAVAILABLE (gRPC's retry policy, A6). SubmitJob and
// Quantize are not retried by the channel: a lost answer would make a second job (SubmitJob
// with a request_id can be retried by the caller, see AIP-155 in the README). WatchJob is not
// either: FollowJob resumes it itself, and a server-streaming call under gRPC 1.51's retry policy
// was seen to hang after a server restart (a batch with a SIGKILLed server: 2 hangs in 8 runs,
// none in 10 without the policy on WatchJob).
constexpr char kRetryMethods[] = R"json(
  "methodConfig": [{
    "name": [
      {"service": "ispq.v1.Quantizer", "method": "GetJob"},
      {"service": "ispq.v1.Quantizer", "method": "ListJobs"},
      {"service": "ispq.v1.Quantizer", "method": "CancelJob"},
      {"service": "ispq.v1.Quantizer", "method": "GetMesh"},
      {"service": "ispq.v1.Quantizer", "method": "GetServerStats"}
    ],
    "retryPolicy": {
      "maxAttempts": 4,
      "initialBackoff": "0.1s",
      "maxBackoff": "2s",
      "backoffMultiplier": 2,
      "retryableStatusCodes": ["UNAVAILABLE"]
    }
  }])json";

absl::StatusOr<std::string> ServiceConfig(const std::string& lb_policy) {
  if (lb_policy.empty()) return absl::StrCat("{", kRetryMethods, "}");
  if (lb_policy != "round_robin" && lb_policy != "pick_first") {
    return absl::InvalidArgumentError(absl::StrCat("load-balancing policy \"", lb_policy,
                                                   "\" is not one of round_robin, pick_first"));
  }
  return absl::StrCat(R"json({"loadBalancingConfig": [{")json", lb_policy, R"json(": {}}],)json",
                      kRetryMethods, "}");
}

}  // namespace

std::string ChannelTarget(const std::string& address) {
  if (!absl::StrContains(address, ',') || absl::StrContains(address, ":/") ||
      absl::StartsWith(address, "ipv4:") || absl::StartsWith(address, "ipv6:")) {
    return address;
  }
  return absl::StrCat(absl::StartsWith(address, "[") ? "ipv6:" : "ipv4:", address);
}

std::string ChannelAuthority(const std::string& address) {
  const std::string target = ChannelTarget(address);
  for (const absl::string_view scheme : {"ipv4:", "ipv6:"}) {
    if (!absl::StartsWith(target, scheme)) continue;
    absl::string_view addresses = absl::StripPrefix(target, scheme);
    addresses = absl::StripPrefix(addresses, "//");
    if (!absl::StrContains(addresses, ',')) return "";
    return std::string(addresses.substr(0, addresses.find(',')));
  }
  return "";
}

absl::StatusOr<std::shared_ptr<grpc::Channel>> OpenChannel(const ServerConnection& connection) {
  if (connection.address.empty()) return absl::InvalidArgumentError("no server address given");
  absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> credentials = Credentials(connection);
  if (!credentials.ok()) return credentials.status();
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(kMaxReceiveMessageBytes);
  arguments.SetMaxSendMessageSize(-1);  // the server enforces its own limit
  absl::StatusOr<std::string> service_config = ServiceConfig(connection.lb_policy);
  if (!service_config.ok()) return service_config.status();
  arguments.SetServiceConfigJSON(*service_config);
  if (const std::string authority = ChannelAuthority(connection.address); !authority.empty()) {
    arguments.SetString(GRPC_ARG_DEFAULT_AUTHORITY, authority);
  }
  return grpc::CreateCustomChannel(ChannelTarget(connection.address), *credentials, arguments);
}

}  // namespace ispq::client
