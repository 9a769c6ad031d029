// SPDX-License-Identifier: Apache-2.0
// The JSON API over jobs, each route one call of the transport-neutral JobService operations
// (server/service/job_service.h), so that it has the gRPC method's semantics and errors:
//
//   POST /v1/jobs               SubmitJob: body an ispq.v1.QuantizeRequest in JSON (a mesh or a
//                               stored_mesh, options, request_id), or in binary protobuf
//                               (Content-Type: application/x-protobuf); answer the Job
//   GET  /v1/jobs/{id}          GetJob (?view=BASIC|FULL, default FULL)
//   GET  /v1/jobs               ListJobs, newest first (?state=RUNNING&pageSize=N&pageToken=T
//                               &view=BASIC|FULL, default BASIC); answer a ListJobsResponse
//   POST /v1/jobs/{id}:cancel   CancelJob; answer the Job
//
// The watch route is server/http/event_stream_route.h. Every route authenticates its caller
// from the request's head, before a body is read. A submission's body is checked
// (server/http/json_guard.h) and converted on the parse threads, with the converted request's
// memory reserved first; the answer comes when the service has admitted or refused it, without a
// thread waiting for it, or after HttpLimits::answer_timeout as DEADLINE_EXCEEDED (retry with the
// same requestId to learn what became of it). The other routes run on the lookup threads, since
// the job store may take its time.
#ifndef ISPQ_SERVER_HTTP_JOB_ROUTES_H_
#define ISPQ_SERVER_HTTP_JOB_ROUTES_H_

#include "server/http/geometry_cache.h"
#include "server/http/http_parts.h"
#include "server/http/http_router.h"

namespace ispq::server::http {

// `parts` (and `geometry`, if given) must outlive `router`. `geometry`: where a submitted job's
// mesh is remembered for the web view (server/http/geometry_cache.h); null: nowhere.
void AddJobRoutes(Router& router, const HttpParts& parts, const HttpLimits& limits,
                  GeometryCache* geometry = nullptr);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_JOB_ROUTES_H_
