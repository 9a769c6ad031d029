// SPDX-License-Identifier: Apache-2.0
// Protobuf's JSON mapping for the HTTP side: responses and events are the API's messages printed
// as JSON (lowerCamelCase names, enums by name, 64-bit integers as strings, zeros printed as the
// CLI's result files have them), and request bodies are converted from JSON straight to the
// binary wire format, without building the message. The binary request then enters the server
// exactly as a gRPC request does (server/admission/raw_request.h): the same memory accounting, the
// same estimate before parsing, the same parser and limits.
#ifndef ISPQ_SERVER_HTTP_PROTO_JSON_H_
#define ISPQ_SERVER_HTTP_PROTO_JSON_H_

#include <string>
#include <string_view>

#include "absl/status/statusor.h"
#include "google/protobuf/descriptor.h"
#include "google/protobuf/message.h"

namespace ispq::server::http {

// The message as one line of JSON (no newline inside, so it fits one SSE data line).
std::string ToJson(const google::protobuf::Message& message);

// The binary form of a `type` message given in JSON; INVALID_ARGUMENT naming the problem (an
// unknown field, a value of the wrong type, malformed JSON) otherwise.
absl::StatusOr<std::string> JsonToBinary(const google::protobuf::Descriptor& type,
                                         std::string_view json);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_PROTO_JSON_H_
