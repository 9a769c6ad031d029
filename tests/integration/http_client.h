// SPDX-License-Identifier: Apache-2.0
// A small HTTP/1.1 client over a plain socket for the tests of the HTTP side: one request per
// connection (Connection: close), the answer read whole or, for event streams, handed over as
// it arrives (chunked bodies decoded). Every read and write has a timeout.
#ifndef ISPQ_TESTS_INTEGRATION_HTTP_CLIENT_H_
#define ISPQ_TESTS_INTEGRATION_HTTP_CLIENT_H_

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/string_view.h"
#include "absl/time/time.h"

namespace ispq::testing {

using HttpHeaderList = std::vector<std::pair<std::string, std::string>>;

struct HttpReply {
  int status = 0;  // 0: no answer (connection failed or closed first)
  HttpHeaderList headers;
  std::string body;

  // The first header `name` (any case), or "".
  std::string Header(absl::string_view name) const;
};

// Sends `method` `path` to 127.0.0.1:`port` with `headers` (Host and Content-Length are added)
// and `body`, then reads the answer; `on_head` (if set) sees the status and headers once read,
// and `on_body` (if set) gets the body's bytes as they arrive instead of `body`, and stops
// reading by returning false. Gives up after `timeout`.
HttpReply SendHttpRequest(int port, const std::string& method, const std::string& path,
                          const HttpHeaderList& headers, const std::string& body,
                          absl::Duration timeout,
                          const std::function<bool(absl::string_view)>& on_body = nullptr,
                          const std::function<void(const HttpReply&)>& on_head = nullptr);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_INTEGRATION_HTTP_CLIENT_H_
