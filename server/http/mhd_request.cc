// SPDX-License-Identifier: Apache-2.0
#include "server/http/mhd_request.h"

#include <arpa/inet.h>
#include <microhttpd.h>
#include <netinet/in.h>

#include <cstring>
#include <string>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"

namespace ispq::server::http {
namespace {

struct Collected {
  HttpFields* fields;
  bool lower_case_names;
  size_t bytes = 0;
};

MHD_Result Collect(void* target, MHD_ValueKind /*kind*/, const char* key, size_t key_size,
                   const char* value, size_t value_size) {
  auto* collected = static_cast<Collected*>(target);
  std::string name(key, key_size);
  if (collected->lower_case_names) absl::AsciiStrToLower(&name);
  collected->fields->emplace_back(
      std::move(name), value == nullptr ? std::string() : std::string(value, value_size));
  collected->bytes += key_size + value_size + 4;  // ": " and CRLF, or "=" and "&"
  return MHD_YES;
}

std::string PeerOf(MHD_Connection* connection) {
  const MHD_ConnectionInfo* info =
      MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
  if (info == nullptr || info->client_addr == nullptr) return "unknown";
  char text[INET6_ADDRSTRLEN] = {};
  const sockaddr* address = info->client_addr;
  if (address->sa_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(address);
    inet_ntop(AF_INET, &v4->sin_addr, text, sizeof(text));
    return absl::StrCat(text, ":", ntohs(v4->sin_port));
  }
  if (address->sa_family == AF_INET6) {
    const auto* v6 = reinterpret_cast<const sockaddr_in6*>(address);
    inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof(text));
    return absl::StrCat("[", text, "]:", ntohs(v6->sin6_port));
  }
  return "unknown";
}

}  // namespace

HeadSize ReadHead(MHD_Connection* connection, const char* url, const char* method,
                  HttpRequest& request) {
  request.method = method;
  request.path = url;
  request.peer = PeerOf(connection);
  Collected headers{.fields = &request.headers, .lower_case_names = true, .bytes = 0};
  MHD_get_connection_values_n(connection, MHD_HEADER_KIND, &Collect, &headers);
  Collected query{.fields = &request.query, .lower_case_names = false, .bytes = 0};
  MHD_get_connection_values_n(connection, MHD_GET_ARGUMENT_KIND, &Collect, &query);
  return HeadSize{.target_bytes = std::strlen(url) + query.bytes,
                  .header_bytes = headers.bytes,
                  .header_count = request.headers.size()};
}

int SocketOf(MHD_Connection* connection) {
  const MHD_ConnectionInfo* info =
      MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CONNECTION_FD);
  return info == nullptr ? -1 : info->connect_fd;
}

}  // namespace ispq::server::http
