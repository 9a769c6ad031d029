// SPDX-License-Identifier: Apache-2.0
// The live web view: every embedded file is served at its path (and index.html at /), from the
// binary's memory, on the event thread, to any caller of an allowed Host, with headers that keep
// a browser from sniffing types or loading anything from elsewhere, and from caching a page that
// a new server version changes.
#include "server/http/web_routes.h"

#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "server/http/http_router.h"
#include "server/http/web_assets.h"
#include "tests/server/http/http_test_service.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

std::string Header(const HttpResponse& response, const std::string& name) {
  for (const auto& [key, value] : response.headers) {
    if (key == name) return value;
  }
  return "";
}

class WebRoutesTest : public ::testing::Test {
 protected:
  WebRoutesTest() { AddWebRoutes(router_); }

  // The answer to GET `path`; status 0 if there is no such route.
  HttpResponse Get(const std::string& path) {
    std::string id;
    const Route* route = router_.Match("GET", path, &id);
    if (route == nullptr) {
      HttpResponse none;
      none.status = 0;
      return none;
    }
    EXPECT_EQ(route->lane, Lane::kInline) << path;
    EXPECT_FALSE(route->authenticated) << path;
    EXPECT_FALSE(route->any_host) << path;
    HttpRequest request = RouteRequest("GET", path, "", "");
    auto responder = std::make_shared<RecordingResponder>();
    route->handle(request, responder);
    EXPECT_EQ(responder->answers(), 1);
    return responder->WaitForAnswer();
  }

  Router router_;
};

TEST_F(WebRoutesTest, EveryAssetIsServedAtItsPathWithItsType) {
  ASSERT_GE(WebAssets().size(), 3u);  // index.html, app.js, style.css
  for (const WebAsset& asset : WebAssets()) {
    const HttpResponse served = Get(std::string(asset.path));
    EXPECT_EQ(served.status, 200) << asset.path;
    EXPECT_EQ(served.content_type, asset.content_type) << asset.path;
    EXPECT_FALSE(asset.body.empty()) << asset.path;
    // The bytes are the binary's own, not a copy.
    EXPECT_EQ(served.static_body.data(), asset.body.data()) << asset.path;
    EXPECT_EQ(served.static_body.size(), asset.body.size()) << asset.path;
    EXPECT_TRUE(served.body.empty()) << asset.path;
  }
}

TEST_F(WebRoutesTest, TheRootIsTheIndexPage) {
  const HttpResponse root = Get("/");
  const HttpResponse index = Get("/index.html");
  ASSERT_EQ(root.status, 200);
  EXPECT_EQ(root.static_body, index.static_body);
  EXPECT_THAT(root.content_type, HasSubstr("text/html"));
  EXPECT_THAT(std::string(root.static_body), HasSubstr("<html"));
}

TEST_F(WebRoutesTest, AnswersForbidSniffingForeignContentAndStaleCopies) {
  for (const WebAsset& asset : WebAssets()) {
    const HttpResponse served = Get(std::string(asset.path));
    EXPECT_EQ(Header(served, "X-Content-Type-Options"), "nosniff") << asset.path;
    EXPECT_EQ(Header(served, "Cache-Control"), "no-cache") << asset.path;
    const std::string policy = Header(served, "Content-Security-Policy");
    EXPECT_THAT(policy, HasSubstr("default-src 'self'")) << asset.path;
    EXPECT_THAT(policy, HasSubstr("connect-src 'self'")) << asset.path;
  }
}

// The 3-D view's library is Debian's libjs-three, embedded byte for byte at build time from where
// server/http/CMakeLists.txt finds it.
TEST_F(WebRoutesTest, ThreeJsIsDebiansFileAsItIs) {
  for (const auto& [path, file] : std::vector<std::pair<std::string, std::string>>{
           {"/vendor/three.min.js", "/usr/share/javascript/three/three.min.js"},
           {"/vendor/OrbitControls.js",
            "/usr/share/javascript/three/examples/js/controls/OrbitControls.js"}}) {
    std::ifstream in(file, std::ios::binary);
    ASSERT_TRUE(in) << file;
    const std::string installed((std::istreambuf_iterator<char>(in)), {});
    const HttpResponse served = Get(path);
    ASSERT_EQ(served.status, 200) << path;
    EXPECT_THAT(served.content_type, HasSubstr("text/javascript")) << path;
    EXPECT_TRUE(served.static_body == installed) << path << ": not the installed file";
  }
  EXPECT_THAT(std::string(Get("/vendor/three.min.js").static_body), HasSubstr("REVISION=\"111\""));
  EXPECT_THAT(std::string(Get("/index.html").static_body), HasSubstr("/vendor/three.min.js"));
}

TEST_F(WebRoutesTest, OnlyTheEmbeddedFilesAreServed) {
  EXPECT_EQ(Get("/missing.js").status, 0);
  EXPECT_EQ(Get("/../server.cc").status, 0);
  EXPECT_EQ(Get("/index.htm").status, 0);
  std::string id;
  EXPECT_EQ(router_.Match("POST", "/index.html", &id), nullptr);
}

}  // namespace
}  // namespace ispq::server::http
