// SPDX-License-Identifier: Apache-2.0
// A request's head as libmicrohttpd has parsed it, copied into an HttpRequest
// (server/http/http_message.h): the copy stays valid while the connection is suspended and the
// request is read on another thread, and the checks of server/http/request_framing.h and
// server/http/origin_policy.h work on it.
#ifndef ISPQ_SERVER_HTTP_MHD_REQUEST_H_
#define ISPQ_SERVER_HTTP_MHD_REQUEST_H_

#include "server/http/http_message.h"
#include "server/http/request_framing.h"

struct MHD_Connection;

namespace ispq::server::http {

// Fills `request`'s method, path, headers (names in lower case), query and peer; how big the
// head was. From the connection's request callback.
HeadSize ReadHead(MHD_Connection* connection, const char* url, const char* method,
                  HttpRequest& request);

// The connection's socket, or -1.
int SocketOf(MHD_Connection* connection);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_MHD_REQUEST_H_
