// SPDX-License-Identifier: Apache-2.0
// GET /v1/jobs/{id}/geometry: what the web view draws of a job's mesh
// (server/http/mesh_geometry.h), binary (application/octet-stream), from the geometry cache
// (server/http/geometry_cache.h) or built from the job's mesh while it runs. The caller must be
// allowed to see the job (NOT_FOUND otherwise, as for GetJob); a job whose mesh is gone and whose
// geometry was not kept is FAILED_PRECONDITION (400) saying so. On the lookup threads: building the
// geometry of a large mesh takes a moment, and finding the job may wait on the job store.
#ifndef ISPQ_SERVER_HTTP_GEOMETRY_ROUTE_H_
#define ISPQ_SERVER_HTTP_GEOMETRY_ROUTE_H_

#include "server/http/geometry_cache.h"
#include "server/http/http_parts.h"
#include "server/http/http_router.h"

namespace ispq::server::http {

// `parts` and `cache` must outlive `router`.
void AddGeometryRoute(Router& router, const HttpParts& parts, GeometryCache& cache);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_GEOMETRY_ROUTE_H_
