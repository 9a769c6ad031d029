// The live web view: GET / serves index.html, GET /<file> the page's other files
// (server/http/web_assets.h). The page itself only talks to the JSON API and the event streams,
// with the same authentication as any client.
#ifndef ISPQ_SERVER_HTTP_WEB_ROUTES_H_
#define ISPQ_SERVER_HTTP_WEB_ROUTES_H_

#include "httplib.h"

namespace ispq::server::http {

void AddWebRoutes(httplib::Server& server);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_WEB_ROUTES_H_
