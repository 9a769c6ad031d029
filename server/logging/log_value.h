// SPDX-License-Identifier: Apache-2.0
// How a client-controlled string (a mesh name, an error message) appears in a structured log
// line: in double quotes, with quotes, backslashes and control characters escaped and long
// values cut, so that no client can forge or break up log lines.
#ifndef ISPQ_SERVER_LOGGING_LOG_VALUE_H_
#define ISPQ_SERVER_LOGGING_LOG_VALUE_H_

#include <string>

namespace ispq::server {

std::string QuotedLogValue(const std::string& value);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_LOGGING_LOG_VALUE_H_
