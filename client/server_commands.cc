// SPDX-License-Identifier: Apache-2.0
#include "client/server_commands.h"

#include <iostream>

#include "client/exit_codes.h"
#include "client/health_check.h"
#include "client/job_output.h"
#include "client/message_json.h"
#include "client/quantizer_client.h"

namespace ispq::cli {
namespace {

// A health check that takes longer than this is a failing one.
constexpr absl::Duration kHealthTimeout = absl::Seconds(5);

}  // namespace

int RunHealth(const RemoteCommandOptions& options, const std::string& service) {
  absl::StatusOr<std::shared_ptr<grpc::Channel>> channel = client::OpenChannel(options.connection);
  if (!channel.ok()) return ReportError(options.connection.address, channel.status());
  const absl::Duration timeout = std::min(options.deadline, kHealthTimeout);
  const absl::StatusOr<client::ServingStatus> status =
      client::CheckHealth(*channel, service, timeout);
  if (!status.ok()) {
    ReportError(options.connection.address, status.status());
    return kExitUnavailable;
  }
  std::cout << client::ServingStatusName(*status) << "\n";
  return *status == client::ServingStatus::kServing ? kExitOk : kExitUnavailable;
}

int RunServerStats(const RemoteCommandOptions& options) {
  absl::StatusOr<client::QuantizerClient> client =
      client::QuantizerClient::Connect(options.connection);
  if (!client.ok()) return ReportError(options.connection.address, client.status());
  const absl::StatusOr<v1::ServerStats> stats = client->GetServerStats();
  if (!stats.ok()) return ReportError(options.connection.address, stats.status());
  std::cout << MessageToJson(*stats) << "\n";
  return kExitOk;
}

}  // namespace ispq::cli
