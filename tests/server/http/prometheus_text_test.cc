// SPDX-License-Identifier: Apache-2.0
#include "server/http/prometheus_text.h"

#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_split.h"
#include "absl/strings/string_view.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

v1::ServerStats SomeStats() {
  v1::ServerStats stats;
  stats.set_workers(4);
  stats.set_busy_workers(3);
  stats.set_queued_jobs(7);
  stats.set_max_queued_jobs(64);
  v1::JobCounts& retained = *stats.mutable_retained_jobs();
  retained.set_queued(7);
  retained.set_running(3);
  retained.set_succeeded(11);
  retained.set_failed(2);
  retained.set_cancelled(1);
  v1::JobCounts& finished = *stats.mutable_finished_total();
  finished.set_succeeded(110);
  finished.set_failed(20);
  finished.set_cancelled(10);
  stats.set_accepted_total(150);
  stats.set_rejected_queue_full_total(5);
  stats.set_rejected_invalid_total(6);
  stats.set_rejected_memory_total(8);
  stats.set_evicted_results_total(9);
  stats.set_evicted_meshes_total(12);
  stats.set_stored_meshes(13);
  stats.set_admissions_in_progress(2);
  stats.set_shutting_down(true);
  stats.mutable_uptime()->set_seconds(90);
  stats.mutable_uptime()->set_nanos(500'000'000);
  v1::Histogram& solve = *stats.mutable_solve_seconds();
  for (const double bound : {0.1, 1.0, 10.0}) solve.add_upper_bounds(bound);
  for (const int64_t count : {2, 5, 9}) solve.add_cumulative_counts(count);
  solve.set_count(10);
  solve.set_sum(42.25);
  v1::MemoryStats& memory = *stats.mutable_memory();
  memory.set_limit_bytes(1000);
  memory.set_used_bytes(600);
  memory.set_peak_used_bytes(900);
  memory.set_requests_bytes(100);
  memory.set_jobs_bytes(200);
  memory.set_stored_meshes_bytes(150);
  memory.set_results_bytes(120);
  memory.set_responses_bytes(30);
  return stats;
}

HttpGauges SomeGauges() {
  return HttpGauges{.ready = true,
                    .open_event_streams = 3,
                    .open_connections = 17,
                    .late_connections_total = 4,
                    .refused_total = {{413, 2}, {431, 0}}};
}

// The samples of an exposition by "name{labels}", checking its syntax on the way: every sample
// belongs to a family declared by # HELP and # TYPE before it, no family is declared twice, no
// sample appears twice and every value is a number.
std::map<std::string, double> Samples(const std::string& text) {
  std::map<std::string, double> samples;
  std::map<std::string, std::string> types;
  std::set<std::string> helped;
  EXPECT_TRUE(absl::EndsWith(text, "\n"));
  for (const absl::string_view line : absl::StrSplit(text, '\n', absl::SkipEmpty())) {
    const std::vector<absl::string_view> words = absl::StrSplit(line, absl::MaxSplits(' ', 3));
    if (absl::StartsWith(line, "# HELP ")) {
      EXPECT_TRUE(helped.insert(std::string(words[2])).second) << line;
      continue;
    }
    if (absl::StartsWith(line, "# TYPE ")) {
      EXPECT_EQ(words.size(), 4u) << line;
      if (words.size() != 4) continue;
      EXPECT_TRUE(helped.contains(std::string(words[2]))) << "TYPE before HELP: " << line;
      EXPECT_TRUE(types.emplace(words[2], words[3]).second) << line;
      continue;
    }
    const std::vector<absl::string_view> parts = absl::StrSplit(line, ' ');
    EXPECT_EQ(parts.size(), 2u) << line;
    if (parts.size() != 2) continue;
    const absl::string_view series = parts[0];
    const absl::string_view name = series.substr(0, series.find('{'));
    std::string family(name);
    if (!types.contains(family)) {
      for (const absl::string_view suffix : {"_bucket", "_sum", "_count"}) {
        if (absl::EndsWith(name, suffix)) {
          family = std::string(name.substr(0, name.size() - suffix.size()));
        }
      }
      EXPECT_EQ(types[family], "histogram") << line;
    }
    EXPECT_TRUE(absl::StartsWith(family, "ispq_")) << line;
    double value = 0;
    EXPECT_TRUE(absl::SimpleAtod(parts[1], &value)) << line;
    EXPECT_TRUE(samples.emplace(series, value).second) << "twice: " << line;
  }
  return samples;
}

TEST(PrometheusTextTest, IsWellFormedAndDeclaresEveryFamilysType) {
  const std::string text = PrometheusText(SomeStats(), SomeGauges());
  Samples(text);
  EXPECT_THAT(text, HasSubstr("# TYPE ispq_jobs gauge\n"));
  EXPECT_THAT(text, HasSubstr("# TYPE ispq_jobs_finished_total counter\n"));
  EXPECT_THAT(text, HasSubstr("# TYPE ispq_jobs_accepted_total counter\n"));
  EXPECT_THAT(text, HasSubstr("# TYPE ispq_http_refused_total counter\n"));
  EXPECT_THAT(text, HasSubstr("# TYPE ispq_solve_seconds histogram\n"));
  EXPECT_THAT(text, HasSubstr("# TYPE ispq_memory_used_bytes gauge\n"));
}

TEST(PrometheusTextTest, ReportsTheServiceStatsUnderTheirNamesAndLabels) {
  const std::map<std::string, double> samples = Samples(PrometheusText(SomeStats(), SomeGauges()));
  const std::map<std::string, double> expected = {
      {"ispq_jobs{state=\"queued\"}", 7},
      {"ispq_jobs{state=\"running\"}", 3},
      {"ispq_jobs{state=\"succeeded\"}", 11},
      {"ispq_jobs{state=\"failed\"}", 2},
      {"ispq_jobs{state=\"cancelled\"}", 1},
      {"ispq_jobs_finished_total{state=\"succeeded\"}", 110},
      {"ispq_jobs_finished_total{state=\"failed\"}", 20},
      {"ispq_jobs_finished_total{state=\"cancelled\"}", 10},
      {"ispq_jobs_accepted_total", 150},
      {"ispq_requests_rejected_total{reason=\"queue_full\"}", 5},
      {"ispq_requests_rejected_total{reason=\"invalid\"}", 6},
      {"ispq_requests_rejected_total{reason=\"memory\"}", 8},
      {"ispq_evictions_total{kind=\"result\"}", 9},
      {"ispq_evictions_total{kind=\"mesh\"}", 12},
      {"ispq_queue_length", 7},
      {"ispq_queue_capacity", 64},
      {"ispq_workers", 4},
      {"ispq_busy_workers", 3},
      {"ispq_admissions_in_progress", 2},
      {"ispq_stored_meshes", 13},
      {"ispq_memory_budget_bytes", 1000},
      {"ispq_memory_used_bytes", 600},
      {"ispq_memory_peak_used_bytes", 900},
      {"ispq_memory_used_by_kind_bytes{kind=\"requests\"}", 100},
      {"ispq_memory_used_by_kind_bytes{kind=\"jobs\"}", 200},
      {"ispq_memory_used_by_kind_bytes{kind=\"stored_meshes\"}", 150},
      {"ispq_memory_used_by_kind_bytes{kind=\"results\"}", 120},
      {"ispq_memory_used_by_kind_bytes{kind=\"responses\"}", 30},
      {"ispq_uptime_seconds", 90.5},
      {"ispq_shutting_down", 1},
  };
  for (const auto& [series, value] : expected) {
    ASSERT_TRUE(samples.contains(series)) << series;
    EXPECT_EQ(samples.at(series), value) << series;
  }
  // Finished jobs are never queued or running.
  EXPECT_FALSE(samples.contains("ispq_jobs_finished_total{state=\"queued\"}"));
}

TEST(PrometheusTextTest, ReportsTheHttpGauges) {
  const std::map<std::string, double> samples = Samples(PrometheusText(SomeStats(), SomeGauges()));
  EXPECT_EQ(samples.at("ispq_ready"), 1);
  EXPECT_EQ(samples.at("ispq_http_event_streams"), 3);
  EXPECT_EQ(samples.at("ispq_http_connections"), 17);
  EXPECT_EQ(samples.at("ispq_http_late_connections_total"), 4);
  EXPECT_EQ(samples.at("ispq_http_refused_total{status=\"413\"}"), 2);
  EXPECT_EQ(samples.at("ispq_http_refused_total{status=\"431\"}"), 0);
  EXPECT_EQ(Samples(PrometheusText(SomeStats(), HttpGauges{})).at("ispq_ready"), 0);
}

// Cumulative buckets, the +Inf bucket equal to the count, and the sum: what
// histogram_quantile() needs.
TEST(PrometheusTextTest, WritesHistogramsAsCumulativeBuckets) {
  const std::string text = PrometheusText(SomeStats(), SomeGauges());
  EXPECT_THAT(text, HasSubstr("ispq_solve_seconds_bucket{le=\"0.1\"} 2\n"
                              "ispq_solve_seconds_bucket{le=\"1\"} 5\n"
                              "ispq_solve_seconds_bucket{le=\"10\"} 9\n"
                              "ispq_solve_seconds_bucket{le=\"+Inf\"} 10\n"
                              "ispq_solve_seconds_sum 42.25\n"
                              "ispq_solve_seconds_count 10\n"));
  // An empty histogram still has its +Inf bucket, sum and count.
  EXPECT_THAT(text, HasSubstr("ispq_queue_wait_seconds_bucket{le=\"+Inf\"} 0\n"
                              "ispq_queue_wait_seconds_sum 0\n"
                              "ispq_queue_wait_seconds_count 0\n"));
}

// Byte counts and counters are exact integers: rounded to a few significant digits, a budget of
// 4 GiB would read as 4.29497e+09 and a counter past a million would move in steps of ten.
TEST(PrometheusTextTest, WritesLargeCountsExactly) {
  v1::ServerStats stats = SomeStats();
  stats.mutable_memory()->set_limit_bytes(int64_t{4} << 30);
  stats.mutable_memory()->set_used_bytes(1'234'567'891);
  stats.set_accepted_total(12'345'679);
  stats.mutable_uptime()->set_seconds(2'000'000);
  stats.mutable_uptime()->set_nanos(250'000'000);
  const std::string text = PrometheusText(stats, SomeGauges());
  EXPECT_THAT(text, HasSubstr("\nispq_memory_budget_bytes 4294967296\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_memory_used_bytes 1234567891\n"));
  EXPECT_THAT(text, HasSubstr("\nispq_jobs_accepted_total 12345679\n"));
  EXPECT_EQ(Samples(text).at("ispq_uptime_seconds"), 2'000'000.25);
}

}  // namespace
}  // namespace ispq::server::http
