// The JSON API over jobs, each route one call of the transport-neutral QuantizerService
// operations (server/quantizer_service.h), so that it has the gRPC method's semantics and errors:
//
//   POST /v1/jobs               SubmitJob: body an ispq.v1.QuantizeRequest in JSON (a mesh or a
//                               stored_mesh, options, request_id); answer the Job
//   GET  /v1/jobs/{id}          GetJob (?view=BASIC|FULL, default FULL)
//   GET  /v1/jobs               ListJobs, newest first (?state=RUNNING&pageSize=N&pageToken=T
//                               &view=BASIC|FULL, default BASIC); answer a ListJobsResponse
//   POST /v1/jobs/{id}:cancel   CancelJob; answer the Job
//
// The watch route is server/http/event_stream_route.h.
#ifndef ISPQ_SERVER_HTTP_JOB_ROUTES_H_
#define ISPQ_SERVER_HTTP_JOB_ROUTES_H_

#include "httplib.h"
#include "server/http/http_parts.h"

namespace ispq::server::http {

// `parts` must outlive `server`.
void AddJobRoutes(httplib::Server& server, const HttpParts& parts, const HttpLimits& limits);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_JOB_ROUTES_H_
