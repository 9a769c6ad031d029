// SPDX-License-Identifier: Apache-2.0
// `ispq stats FILE [--json]`: loads and validates a T-mesh and prints its counts.
#ifndef ISPQ_CLIENT_STATS_COMMAND_H_
#define ISPQ_CLIENT_STATS_COMMAND_H_

#include <string>

namespace ispq::cli {

int RunStatsCommand(const std::string& path, bool json);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_STATS_COMMAND_H_
