#include "server/http/web_routes.h"

#include <string>

#include "server/http/web_assets.h"

namespace ispq::server::http {
namespace {

void Serve(const WebAsset& asset, httplib::Response& response) {
  response.set_header("Cache-Control", "no-cache");  // a new server version shows at once
  response.set_header("X-Content-Type-Options", "nosniff");
  response.set_header("Content-Security-Policy",
                      "default-src 'self'; img-src 'self' data: blob:; connect-src 'self' blob:");
  response.set_content(std::string(asset.body), std::string(asset.content_type));
}

}  // namespace

void AddWebRoutes(httplib::Server& server) {
  for (const WebAsset& asset : WebAssets()) {
    server.Get(
        std::string(asset.path),
        [&asset](const httplib::Request&, httplib::Response& response) { Serve(asset, response); });
    if (asset.path == "/index.html") {
      server.Get("/", [&asset](const httplib::Request&, httplib::Response& response) {
        Serve(asset, response);
      });
    }
  }
}

}  // namespace ispq::server::http
