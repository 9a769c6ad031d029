// SPDX-License-Identifier: Apache-2.0
// The server's stats (GetServerStats' ispq.v1.ServerStats) in the Prometheus text exposition
// format 0.0.4, for GET /metrics: gauges of the present (jobs by state, queue length, busy
// workers, memory budget use by kind, readiness), counters since the start (accepted jobs,
// rejections by reason, evictions, finished jobs by state) and the solve-time and queue-wait
// histograms. Names are prefixed `ispq_`; units are seconds and bytes.
#ifndef ISPQ_SERVER_HTTP_PROMETHEUS_TEXT_H_
#define ISPQ_SERVER_HTTP_PROMETHEUS_TEXT_H_

#include <cstdint>
#include <map>
#include <string>

#include "ispq/v1/service.pb.h"

namespace ispq::server::http {

// What the HTTP side adds to the service's stats.
struct HttpGauges {
  bool ready = false;
  int open_event_streams = 0;
  int open_connections = 0;
  int64_t late_connections_total = 0;    // shut down past their head or body deadline
  std::map<int, int64_t> refused_total;  // by HTTP status
};

std::string PrometheusText(const v1::ServerStats& stats, const HttpGauges& http);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_PROMETHEUS_TEXT_H_
