// SPDX-License-Identifier: Apache-2.0
// The `ispq` subcommands for operators of a server:
//
//   ispq health --server HOST:PORT    prints SERVING (exit 0) or why not (exit 6); what the
//                                     container image's HEALTHCHECK runs
//   ispq server-stats --server ...    prints the server's counters as JSON
#ifndef ISPQ_CLIENT_SERVER_COMMANDS_H_
#define ISPQ_CLIENT_SERVER_COMMANDS_H_

#include <string>

#include "client/remote_command_options.h"

namespace ispq::cli {

// `service`: "" for liveness, "readiness" for readiness (see the README).
int RunHealth(const RemoteCommandOptions& options, const std::string& service = "");
int RunServerStats(const RemoteCommandOptions& options);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_SERVER_COMMANDS_H_
