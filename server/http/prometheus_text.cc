// SPDX-License-Identifier: Apache-2.0
#include "server/http/prometheus_text.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "google/protobuf/util/time_util.h"

namespace ispq::server::http {
namespace {

// Appends one metric family; `samples` are (label set, value), the label set "" or `{k="v"}`.
class Exposition {
 public:
  void Family(const char* name, const char* type, const char* help,
              const std::vector<std::pair<std::string, double>>& samples) {
    absl::StrAppend(&text_, "# HELP ", name, " ", help, "\n# TYPE ", name, " ", type, "\n");
    for (const auto& [labels, value] : samples) {
      absl::StrAppend(&text_, name, labels, " ", Number(value), "\n");
    }
  }
  void Single(const char* name, const char* type, const char* help, double value) {
    Family(name, type, help, {{"", value}});
  }
  void Histogram(const char* name, const char* help, const v1::Histogram& histogram) {
    absl::StrAppend(&text_, "# HELP ", name, " ", help, "\n# TYPE ", name, " histogram\n");
    for (int i = 0; i < histogram.upper_bounds_size(); ++i) {
      absl::StrAppend(&text_, name, "_bucket{le=\"", Number(histogram.upper_bounds(i)), "\"} ",
                      histogram.cumulative_counts(i), "\n");
    }
    absl::StrAppend(&text_, name, "_bucket{le=\"+Inf\"} ", histogram.count(), "\n", name, "_sum ",
                    Number(histogram.sum()), "\n", name, "_count ", histogram.count(), "\n");
  }
  std::string Take() { return std::move(text_); }

 private:
  // Counts and bytes exactly, anything else as the shortest text that reads back as the same
  // double: absl::StrCat keeps six significant digits, so a 4 GiB budget would read 4.29497e+09
  // and a counter past a million would move in steps of ten.
  static std::string Number(double value) {
    if (std::abs(value) < 0x1p53 && value == std::trunc(value)) {
      return absl::StrCat(static_cast<int64_t>(value));
    }
    char buffer[32];
    return std::string(buffer, std::to_chars(buffer, buffer + sizeof(buffer), value).ptr);
  }
  std::string text_;
};

std::vector<std::pair<std::string, double>> ByState(const v1::JobCounts& counts, bool with_active) {
  std::vector<std::pair<std::string, double>> samples;
  if (with_active) {
    samples.emplace_back("{state=\"queued\"}", counts.queued());
    samples.emplace_back("{state=\"running\"}", counts.running());
  }
  samples.emplace_back("{state=\"succeeded\"}", counts.succeeded());
  samples.emplace_back("{state=\"failed\"}", counts.failed());
  samples.emplace_back("{state=\"cancelled\"}", counts.cancelled());
  return samples;
}

}  // namespace

std::string PrometheusText(const v1::ServerStats& stats, const HttpGauges& http) {
  Exposition out;
  out.Family("ispq_jobs", "gauge", "Jobs the server holds now, by state.",
             ByState(stats.retained_jobs(), /*with_active=*/true));
  out.Family("ispq_jobs_finished_total", "counter",
             "Jobs that ended since the server started, by final state.",
             ByState(stats.finished_total(), /*with_active=*/false));
  out.Single("ispq_jobs_accepted_total", "counter", "Jobs accepted since the server started.",
             static_cast<double>(stats.accepted_total()));
  out.Family("ispq_requests_rejected_total", "counter",
             "Requests refused since the server started, by reason.",
             {{"{reason=\"queue_full\"}", static_cast<double>(stats.rejected_queue_full_total())},
              {"{reason=\"invalid\"}", static_cast<double>(stats.rejected_invalid_total())},
              {"{reason=\"memory\"}", static_cast<double>(stats.rejected_memory_total())}});
  out.Family("ispq_evictions_total", "counter",
             "Retained results and stored meshes dropped early to make room in the memory budget.",
             {{"{kind=\"result\"}", static_cast<double>(stats.evicted_results_total())},
              {"{kind=\"mesh\"}", static_cast<double>(stats.evicted_meshes_total())}});
  out.Single("ispq_queue_length", "gauge", "Jobs waiting for a worker.", stats.queued_jobs());
  out.Single("ispq_queue_capacity", "gauge", "Jobs that may wait for a worker (--max_queued_jobs).",
             stats.max_queued_jobs());
  out.Single("ispq_workers", "gauge", "Worker threads (--workers).", stats.workers());
  out.Single("ispq_busy_workers", "gauge", "Workers running a job now.", stats.busy_workers());
  out.Single("ispq_admissions_in_progress", "gauge",
             "Requests received and not yet parsed and validated.", stats.admissions_in_progress());
  out.Single("ispq_stored_meshes", "gauge", "Meshes stored with CreateMesh.",
             stats.stored_meshes());
  out.Histogram("ispq_solve_seconds", "In-process solve time of finished runs.",
                stats.solve_seconds());
  out.Histogram("ispq_queue_wait_seconds", "Time from acceptance to the start of a run.",
                stats.queue_wait_seconds());
  const v1::MemoryStats& memory = stats.memory();
  out.Single("ispq_memory_budget_bytes", "gauge", "The memory budget (--max_memory_bytes).",
             static_cast<double>(memory.limit_bytes()));
  out.Single("ispq_memory_used_bytes", "gauge", "Memory accounted against the budget now.",
             static_cast<double>(memory.used_bytes()));
  out.Single("ispq_memory_peak_used_bytes", "gauge",
             "The most memory accounted against the budget since the server started.",
             static_cast<double>(memory.peak_used_bytes()));
  out.Family("ispq_memory_used_by_kind_bytes", "gauge",
             "Memory accounted against the budget now, by what holds it.",
             {{"{kind=\"requests\"}", static_cast<double>(memory.requests_bytes())},
              {"{kind=\"jobs\"}", static_cast<double>(memory.jobs_bytes())},
              {"{kind=\"stored_meshes\"}", static_cast<double>(memory.stored_meshes_bytes())},
              {"{kind=\"results\"}", static_cast<double>(memory.results_bytes())},
              {"{kind=\"responses\"}", static_cast<double>(memory.responses_bytes())}});
  out.Single(
      "ispq_uptime_seconds", "gauge", "Time since the server started.",
      static_cast<double>(google::protobuf::util::TimeUtil::DurationToNanoseconds(stats.uptime())) /
          1e9);
  out.Single("ispq_shutting_down", "gauge", "1 once graceful shutdown has begun.",
             stats.shutting_down() ? 1 : 0);
  out.Single("ispq_ready", "gauge", "1 while the server would accept a new job (as /readyz).",
             http.ready ? 1 : 0);
  out.Single("ispq_http_event_streams", "gauge", "Server-sent-event streams open now.",
             http.open_event_streams);
  out.Single("ispq_http_connections", "gauge", "HTTP connections open now.", http.open_connections);
  out.Single("ispq_http_late_connections_total", "counter",
             "HTTP connections shut down because a request's head or body came too slowly.",
             static_cast<double>(http.late_connections_total));
  std::vector<std::pair<std::string, double>> refused;
  for (const auto& [status, count] : http.refused_total) {
    refused.emplace_back(absl::StrCat("{status=\"", status, "\"}"), static_cast<double>(count));
  }
  out.Family("ispq_http_refused_total", "counter",
             "HTTP requests refused before their route ran, by HTTP status.", refused);
  return out.Take();
}

}  // namespace ispq::server::http
