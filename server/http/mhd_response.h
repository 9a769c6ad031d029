// SPDX-License-Identifier: Apache-2.0
// An HttpResponse (server/http/http_message.h) handed to libmicrohttpd. A held body is given
// over without a copy and freed with its memory reservation once sent; a streamed body is asked
// for its next bytes whenever the connection can take them, and suspends the connection while it
// has none (no thread waits for it). A refusal that must be sent while a body is still arriving,
// when libmicrohttpd takes no response, is written straight to the socket before the connection
// is closed.
#ifndef ISPQ_SERVER_HTTP_MHD_RESPONSE_H_
#define ISPQ_SERVER_HTTP_MHD_RESPONSE_H_

#include "absl/status/status.h"
#include "server/http/http_message.h"
#include "server/http/suspensions.h"
#include "server/memory/memory_budget.h"

struct MHD_Connection;

namespace ispq::server::http {

// Queues `response` on `connection` (from its request callback); false if libmicrohttpd did not
// take it (the connection is then closed). `budget` accounts for a streamed body's bytes in
// flight; it and `suspensions` must outlive the connection.
bool QueueResponse(MHD_Connection* connection, HttpResponse response, MemoryBudget& budget,
                   Suspensions& suspensions);

// Writes `status` as a complete response with `Connection: close` to the connection's socket,
// which the caller then has libmicrohttpd close. Only while the request's body is arriving (no
// response bytes have been sent) and from the connection's request callback.
void WriteRefusal(MHD_Connection* connection, const absl::Status& status);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_MHD_RESPONSE_H_
