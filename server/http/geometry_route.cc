// SPDX-License-Identifier: Apache-2.0
#include "server/http/geometry_route.h"

#include <memory>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "server/http/http_exchange.h"
#include "server/model/resource_names.h"

namespace ispq::server::http {
namespace {

void GetGeometry(const HttpParts& parts, GeometryCache& cache, HttpRequest& request,
                 const std::shared_ptr<Responder>& responder) {
  v1::WatchJobRequest find;  // the lookup that checks the caller may see the job
  find.set_name(absl::StrCat(kJobCollection, "/", request.id));
  absl::StatusOr<WatchTarget> target = parts.service.Watch(find, request.principal);
  if (!target.ok()) return responder->Answer(ErrorResponse(target.status()));
  absl::StatusOr<std::shared_ptr<const std::string>> geometry =
      cache.Get(find.name(), target->job->mesh());
  if (!geometry.ok()) return responder->Answer(ErrorResponse(geometry.status()));
  absl::StatusOr<MemoryReservation> reserved = parts.memory.Reserve(
      MemoryUse::kResponses, static_cast<int64_t>((*geometry)->size()), "the geometry response");
  if (!reserved.ok()) return responder->Answer(ErrorResponse(reserved.status()));
  HttpResponse response;
  response.content_type = "application/octet-stream";
  // A job's mesh never changes; the page may keep what it fetched.
  response.headers.emplace_back("Cache-Control", "private, max-age=3600");
  response.headers.emplace_back("X-Content-Type-Options", "nosniff");
  response.body = **geometry;
  response.memory = *std::move(reserved);
  responder->Answer(std::move(response));
}

}  // namespace

void AddGeometryRoute(Router& router, const HttpParts& parts, GeometryCache& cache) {
  Route route;
  route.method = "GET";
  route.pattern = "/v1/jobs/{id}/geometry";
  route.lane = Lane::kLookup;
  route.authenticated = true;
  route.handle = [&parts, &cache](HttpRequest& request,
                                  const std::shared_ptr<Responder>& responder) {
    GetGeometry(parts, cache, request, responder);
  };
  router.Add(std::move(route));
}

}  // namespace ispq::server::http
