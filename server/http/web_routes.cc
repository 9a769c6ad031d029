// SPDX-License-Identifier: Apache-2.0
#include "server/http/web_routes.h"

#include <memory>
#include <string>

#include "server/http/web_assets.h"

namespace ispq::server::http {
namespace {

HttpResponse Serve(const WebAsset& asset) {
  HttpResponse response;
  response.headers.emplace_back("Cache-Control", "no-cache");  // a new server version shows at once
  response.headers.emplace_back("X-Content-Type-Options", "nosniff");
  response.headers.emplace_back(
      "Content-Security-Policy",
      "default-src 'self'; img-src 'self' data: blob:; connect-src 'self' blob:");
  response.content_type = std::string(asset.content_type);
  response.static_body = absl::string_view(asset.body.data(), asset.body.size());
  return response;
}

void AddAsset(Router& router, std::string path, const WebAsset& asset) {
  Route route;
  route.method = "GET";
  route.pattern = std::move(path);
  route.handle = [&asset](HttpRequest&, const std::shared_ptr<Responder>& responder) {
    responder->Answer(Serve(asset));
  };
  router.Add(std::move(route));
}

}  // namespace

void AddWebRoutes(Router& router) {
  for (const WebAsset& asset : WebAssets()) {
    AddAsset(router, std::string(asset.path), asset);
    if (asset.path == "/index.html") AddAsset(router, "/", asset);
  }
}

}  // namespace ispq::server::http
