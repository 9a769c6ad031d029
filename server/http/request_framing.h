// SPDX-License-Identifier: Apache-2.0
// The checks of a request's head that decide, before any byte of its body is read, whether and
// how the body is read. The request target and the header lines are bounded (414 and 431); a
// body must say how long it is or come chunked (411), be no longer than the limit (413), be
// neither compressed nor in another transfer coding (415 and 501: bodies are never decoded), and
// be JSON where it is read at all (415). Refusals are statuses with their HTTP status attached
// (server/http/http_status.h).
#ifndef ISPQ_SERVER_HTTP_REQUEST_FRAMING_H_
#define ISPQ_SERVER_HTTP_REQUEST_FRAMING_H_

#include <cstddef>
#include <cstdint>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "server/http/http_message.h"
#include "server/http/http_parts.h"

namespace ispq::server::http {

// How big a request's head was.
struct HeadSize {
  size_t target_bytes = 0;  // path and query, as sent
  size_t header_bytes = 0;  // the header lines, as sent
  size_t header_count = 0;
};

absl::Status CheckHeadSize(const HeadSize& size, const HttpLimits& limits);

struct BodyFraming {
  bool chunked = false;
  int64_t length = 0;  // the declared length, without chunks
};

// How the body arrives (a GET without either header has none).
absl::StatusOr<BodyFraming> PlanBody(const HttpRequest& request, int64_t max_body_bytes);

// 415 unless the Content-Type is application/json (with at most `charset=utf-8`), or, with
// `protobuf_too`, application/x-protobuf (no parameters).
absl::Status CheckJsonContentType(const HttpRequest& request, bool protobuf_too = false);

// Whether the body is binary protobuf (its Content-Type application/x-protobuf); only meaningful
// once CheckJsonContentType(request, true) passed.
bool IsProtobufBody(const HttpRequest& request);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_REQUEST_FRAMING_H_
