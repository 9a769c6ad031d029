// SPDX-License-Identifier: Apache-2.0
#include "client/message_json.h"

#include "google/protobuf/util/json_util.h"

namespace ispq::cli {

std::string MessageToJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  std::string json;
  // Printing a well-formed message cannot fail; the status carries nothing to act on.
  (void)google::protobuf::util::MessageToJsonString(message, &json, options);
  return json;
}

}  // namespace ispq::cli
