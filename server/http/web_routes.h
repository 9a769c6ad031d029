// SPDX-License-Identifier: Apache-2.0
// The live web view: GET / serves index.html, GET /<file> the page's other files
// (server/http/web_assets.h). The page itself only talks to the JSON API and the event streams,
// with the same authentication as any client. The files are served on the event thread, from
// the binary's own memory.
#ifndef ISPQ_SERVER_HTTP_WEB_ROUTES_H_
#define ISPQ_SERVER_HTTP_WEB_ROUTES_H_

#include "server/http/http_router.h"

namespace ispq::server::http {

void AddWebRoutes(Router& router);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_WEB_ROUTES_H_
