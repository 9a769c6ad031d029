// SPDX-License-Identifier: Apache-2.0
// The web view's static files (server/http/web/), compiled into the server by
// server/http/embed_web_assets.cmake: the page works with nothing installed next to the binary
// and loads nothing from the network (no CDN, no build step that downloads).
#ifndef ISPQ_SERVER_HTTP_WEB_ASSETS_H_
#define ISPQ_SERVER_HTTP_WEB_ASSETS_H_

#include <string_view>
#include <vector>

namespace ispq::server::http {

struct WebAsset {
  std::string_view path;          // "/index.html"
  std::string_view content_type;  // "text/html; charset=utf-8"
  std::string_view body;
};

const std::vector<WebAsset>& WebAssets();

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_WEB_ASSETS_H_
