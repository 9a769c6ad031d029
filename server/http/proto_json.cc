// SPDX-License-Identifier: Apache-2.0
#include "server/http/proto_json.h"

#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "google/protobuf/descriptor.h"
#include "google/protobuf/util/json_util.h"
#include "google/protobuf/util/type_resolver.h"
#include "google/protobuf/util/type_resolver_util.h"

namespace ispq::server::http {
namespace {

constexpr char kTypeUrlPrefix[] = "type.googleapis.com";

// Shared by all threads: the resolver only reads the generated pool.
google::protobuf::util::TypeResolver& Resolver() {
  static google::protobuf::util::TypeResolver* const resolver =
      google::protobuf::util::NewTypeResolverForDescriptorPool(
          kTypeUrlPrefix, google::protobuf::DescriptorPool::generated_pool());
  return *resolver;
}

}  // namespace

std::string ToJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;  // as the CLI's result files
  std::string json;
  const auto printed = google::protobuf::util::MessageToJsonString(message, &json, options);
  if (!printed.ok()) return "{}";  // only for messages with invalid UTF-8, which we never build
  return json;
}

absl::StatusOr<std::string> JsonToBinary(const google::protobuf::Descriptor& type,
                                         std::string_view json) {
  std::string binary;
  const auto converted = google::protobuf::util::JsonToBinaryString(
      &Resolver(), absl::StrCat(kTypeUrlPrefix, "/", type.full_name()),
      google::protobuf::StringPiece(json.data(), json.size()), &binary);
  if (!converted.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("the body is not a ", type.full_name(),
                                                   " in JSON: ", converted.message().ToString()));
  }
  return binary;
}

}  // namespace ispq::server::http
