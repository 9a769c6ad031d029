// SPDX-License-Identifier: Apache-2.0
// The CLI's JSON output: any ispq.v1 message in protobuf's JSON mapping with every field written,
// since `valid: false`, zero counts and empty lists are answers too. Every command that prints
// or writes JSON goes through here, so all of them look alike.
#ifndef ISPQ_CLIENT_MESSAGE_JSON_H_
#define ISPQ_CLIENT_MESSAGE_JSON_H_

#include <string>

#include "google/protobuf/message.h"

namespace ispq::cli {

std::string MessageToJson(const google::protobuf::Message& message);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_MESSAGE_JSON_H_
