// SPDX-License-Identifier: Apache-2.0
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
  // HOST:PORT; several as HOST:PORT,HOST:PORT (one channel over all of them); or any gRPC
  // target URI, e.g. dns:///ispq-server-headless.ispq.svc:50051 (every address the name
  // resolves to, re-resolved when a connection ends).
  std::string address = "127.0.0.1:50051";
  // gRPC's load-balancing policy over the target's addresses: "pick_first" (gRPC's default: one
  // connection, to the first address that works) or "round_robin" (a connection to every
  // address, calls spread over them in turn). Empty: gRPC's default.
  std::string lb_policy;
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

// The channel (connected lazily by gRPC), with `lb_policy` and a retry policy: idempotent calls
// (GetJob, ListJobs, CancelJob, GetMesh, GetServerStats; WatchJob is resumed by FollowJob) that
// meet UNAVAILABLE, such as a replica going away, are retried up to 3 more times with backoff,
// on another address under round_robin. INVALID_ARGUMENT for an unknown policy, INVALID_ARGUMENT
// or NOT_FOUND for unusable TLS files.
absl::StatusOr<std::shared_ptr<grpc::Channel>> OpenChannel(const ServerConnection& connection);

// The gRPC target for `address`: HOST:PORT,HOST:PORT becomes ipv4:/ipv6: address lists (gRPC
// takes a bare comma-separated list as one DNS name); anything else is returned as is.
std::string ChannelTarget(const std::string& address);

// The authority of a channel to an address list (HOST:PORT,HOST:PORT, ipv4:..., ipv6:...): its
// first address. gRPC would otherwise take the whole list as the authority, the name TLS verifies
// the server's certificate against, and refuse every replica ("Peer name 10.0.0.1:1,10.0.0.2:2 is
// not in peer certificate"). Empty for anything else (gRPC's default is right).
std::string ChannelAuthority(const std::string& address);

}  // namespace ispq::client

#endif  // ISPQ_CLIENT_SERVER_CONNECTION_H_
