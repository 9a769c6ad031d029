// SPDX-License-Identifier: Apache-2.0
// Load test of the quantization service (not part of the default test run; a small bounded
// variant is, see CMakeLists.txt): C concurrent clients each run J jobs through the real
// ispq-server on loopback, over the real T-meshes at several levels, bounded in count
// and time. It reports throughput and latency percentiles, checks that every job's result is
// present and valid (the validator) and identical to an in-process solve of the same instance
// (nothing lost, nothing wrong), and measures the server's overhead over in-process solves.
//
//   ispq_load_test [--clients 8] [--jobs_per_client 100] [--workers 2] [--levels 1,10,25,100]
//                  [--max_seconds 900] [--out table.md]
//
// Exits 0 if every job came back with a valid result equal to the in-process one, 1 otherwise.
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "client/quantizer_client.h"
#include "core/proto/quantization_proto.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/quantization_validator.h"
#include "core/quantizer.h"
#include "tests/integration/server_process.h"
#include "tests/support/test_data.h"

ABSL_FLAG(int, clients, 8, "concurrent clients, each with its own channel");
ABSL_FLAG(int, jobs_per_client, 100, "jobs each client runs, one after the other");
ABSL_FLAG(int, workers, 2, "worker threads of the server");
ABSL_FLAG(std::string, levels, "1,10,25,100", "resolution levels of the instances");
ABSL_FLAG(double, max_seconds, 900, "stop starting jobs after this long (the run is bounded)");
ABSL_FLAG(std::vector<std::string>, server_flags, {},
          "more flags for the server, comma-separated (e.g. --http_listen=127.0.0.1:8080 to "
          "measure the HTTP side's overhead)");
ABSL_FLAG(std::string, out, "", "also write the report (Markdown) to this file");

namespace ispq::testing {
namespace {

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Instance {
  std::string name;  // "<dataset>/<model>@<level>"
  std::shared_ptr<const v1::TMesh> proto;
  std::shared_ptr<const TMesh> mesh;
  v1::QuantizationOptions options;
  // The in-process reference: same code, one thread, no server.
  std::vector<int64_t> local_q;
  double local_wall_seconds = 0;  // Quantize() call, measured around it
};

struct JobRecord {
  int instance = -1;
  bool done = false;
  absl::Status status;
  double latency_seconds = 0;  // request sent to final event received
  v1::QuantizationResult result;
};

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t rank = static_cast<size_t>(std::ceil(p / 100.0 * values.size()));
  return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
}

double Mean(const std::vector<double>& values) {
  double sum = 0;
  for (double v : values) sum += v;
  return values.empty() ? 0 : sum / static_cast<double>(values.size());
}

std::vector<Instance> LoadInstances(const std::vector<int>& levels) {
  std::vector<Instance> instances;
  for (const std::string& path : RealTMeshFiles()) {
    auto proto = std::make_shared<const v1::TMesh>(LoadProtoOrDie(path));
    auto mesh = std::make_shared<const TMesh>(TMeshOrDie(*proto));
    for (int level : levels) {
      Instance instance;
      instance.name = absl::StrFormat("%s@%d", ShortName(path), level);
      instance.proto = proto;
      instance.mesh = mesh;
      instance.options.mutable_scaling()->set_level_percent(level);
      instances.push_back(std::move(instance));
    }
  }
  return instances;
}

// Solves every instance in-process once, single-threaded, as the baseline.
void SolveInProcess(std::vector<Instance>& instances) {
  for (Instance& instance : instances) {
    const absl::StatusOr<QuantizeOptions> options =
        QuantizeOptionsFromProto(instance.options, *instance.mesh);
    const Clock::time_point start = Clock::now();
    const absl::StatusOr<QuantizeResult> result = Quantize(*instance.mesh, *options);
    instance.local_wall_seconds = SecondsSince(start);
    if (result.ok()) instance.local_q = result->q;
  }
}

v1::QuantizeRequest RequestFor(const Instance& instance) {
  v1::QuantizeRequest request;
  *request.mutable_mesh() = *instance.proto;
  *request.mutable_options() = instance.options;
  return request;
}

// Runs one job through Quantize, retrying while the server asks to (RESOURCE_EXHAUSTED).
JobRecord RunJob(client::QuantizerClient& client, const std::vector<Instance>& instances,
                 int instance) {
  JobRecord record;
  record.instance = instance;
  const v1::QuantizeRequest request = RequestFor(instances[instance]);
  const Clock::time_point start = Clock::now();
  for (int attempt = 0; attempt < 100; ++attempt) {
    client::StreamOptions options;
    options.timeout = absl::Seconds(600);
    const client::JobOutcome outcome = client.Quantize(request, options);
    if (absl::IsResourceExhausted(outcome.status)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      continue;
    }
    record.status = outcome.status;
    if (outcome.result.has_value()) {
      record.done = true;
      record.result = *outcome.result;
    }
    break;
  }
  record.latency_seconds = SecondsSince(start);
  return record;
}

// Whether a job came back with a valid result equal to the in-process one; the reason if not.
std::string CheckJob(const JobRecord& record, const std::vector<Instance>& instances) {
  if (!record.done) return "no result: " + record.status.ToString();
  const Instance& instance = instances[record.instance];
  const absl::StatusOr<std::vector<int64_t>> q =
      QuantizationFromProto(record.result, *instance.mesh);
  if (!q.ok()) return q.status().ToString();
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(*instance.mesh, *q);
  if (!report.ok()) return report.status().ToString();
  if (!report->valid() || !record.result.valid()) return "not valid: " + report->Describe(3);
  if (*q != instance.local_q) return "differs from the in-process result";
  return "";
}

int Main() {
  const int clients = absl::GetFlag(FLAGS_clients);
  const int jobs_per_client = absl::GetFlag(FLAGS_jobs_per_client);
  const int workers = absl::GetFlag(FLAGS_workers);
  std::vector<int> levels;
  for (absl::string_view level : absl::StrSplit(absl::GetFlag(FLAGS_levels), ',')) {
    levels.push_back(std::stoi(std::string(level)));
  }

  std::vector<Instance> instances = LoadInstances(levels);
  if (instances.empty()) {
    std::cerr << "no real T-meshes under " << RealTMeshDir() << "\n";
    return 1;
  }
  const int total_jobs = clients * jobs_per_client;
  // Jobs take instances round robin; only the instances used are solved in-process.
  const int used = std::min<int>(static_cast<int>(instances.size()), total_jobs);
  instances.resize(used);
  std::cerr << "in-process baseline: " << used << " instances...\n";
  SolveInProcess(instances);

  std::vector<std::string> server_flags = {
      absl::StrFormat("--workers=%d", workers), "--log_level=warn",
      absl::StrFormat("--retain_finished_jobs=%d", total_jobs + 100)};
  for (const std::string& flag : absl::GetFlag(FLAGS_server_flags)) server_flags.push_back(flag);
  absl::StatusOr<std::unique_ptr<ServerProcess>> server =
      ServerProcess::Start(ServerBinaryPath(), server_flags);
  if (!server.ok()) {
    std::cerr << server.status() << "\n";
    return 1;
  }
  client::ServerConnection connection;
  connection.address = (*server)->address();

  // Unloaded overhead: one client, each instance once, nothing else running.
  std::cerr << "sequential pass over the server...\n";
  std::vector<double> sequential_overhead;
  std::vector<double> sequential_ratio;
  {
    absl::StatusOr<client::QuantizerClient> client = client::QuantizerClient::Connect(connection);
    for (int i = 0; i < used; ++i) {
      const JobRecord record = RunJob(*client, instances, i);
      if (!record.done) continue;
      sequential_overhead.push_back(record.latency_seconds - instances[i].local_wall_seconds);
      sequential_ratio.push_back(record.latency_seconds /
                                 std::max(instances[i].local_wall_seconds, 1e-6));
    }
  }

  std::cerr << "load: " << clients << " clients x " << jobs_per_client << " jobs...\n";
  const Clock::time_point deadline_start = Clock::now();
  const double max_seconds = absl::GetFlag(FLAGS_max_seconds);
  std::vector<std::vector<JobRecord>> records(clients);
  std::vector<std::thread> threads;
  const Clock::time_point start = Clock::now();
  for (int c = 0; c < clients; ++c) {
    threads.emplace_back([&, c] {
      absl::StatusOr<client::QuantizerClient> client = client::QuantizerClient::Connect(connection);
      for (int j = 0; j < jobs_per_client; ++j) {
        if (SecondsSince(deadline_start) > max_seconds) break;
        const int instance = (c * jobs_per_client + j) % used;
        records[c].push_back(RunJob(*client, instances, instance));
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  const double wall = SecondsSince(start);
  absl::StatusOr<v1::ServerStats> stats =
      client::QuantizerClient::Connect(connection)->GetServerStats();
  (*server)->Signal(SIGTERM);
  const std::optional<int> exit_code = (*server)->WaitForExit(absl::Seconds(120));

  // Every job: present, valid, and the in-process answer.
  int started = 0;
  int failures = 0;
  std::vector<double> latencies;
  std::vector<double> server_solve;
  std::vector<double> local_of_jobs;
  std::vector<std::string> problems;
  for (const std::vector<JobRecord>& client_records : records) {
    for (const JobRecord& record : client_records) {
      ++started;
      const std::string problem = CheckJob(record, instances);
      if (!problem.empty()) {
        ++failures;
        if (problems.size() < 10)
          problems.push_back(instances[record.instance].name + ": " + problem);
        continue;
      }
      latencies.push_back(record.latency_seconds);
      server_solve.push_back(record.result.stats().solve_seconds());
      local_of_jobs.push_back(instances[record.instance].local_wall_seconds);
    }
  }
  const bool bounded_out = started < total_jobs;
  double local_total = 0;
  for (double s : local_of_jobs) local_total += s;
  double solve_total = 0;
  for (double s : server_solve) solve_total += s;
  const double throughput = static_cast<double>(latencies.size()) / wall;
  const double ideal = workers * static_cast<double>(local_of_jobs.size()) / local_total;

  std::ostringstream report;
  report << "# ispq service load test\n\n"
         << absl::StrFormat(
                "%d clients x %d jobs (%d started, %d instances: %zu real "
                "T-meshes x levels %s), server with %d workers on loopback, %u "
                "hardware threads\n\n",
                clients, jobs_per_client, started, used, RealTMeshFiles().size(),
                absl::StrJoin(levels, ","), workers, std::thread::hardware_concurrency())
         << "| measure | value |\n| --- | --- |\n"
         << absl::StrFormat("| jobs with a valid result equal to in-process | %zu / %d |\n",
                            latencies.size(), started)
         << absl::StrFormat("| wall time | %.2f s |\n", wall)
         << absl::StrFormat("| throughput | %.2f jobs/s |\n", throughput)
         << absl::StrFormat(
                "| ideal throughput (%d workers x in-process solve times) | %.2f "
                "jobs/s |\n",
                workers, ideal)
         << absl::StrFormat("| efficiency (throughput / ideal) | %.1f %% |\n",
                            100 * throughput / ideal)
         << absl::StrFormat("| latency p50 / p95 / p99 / max | %.1f / %.1f / %.1f / %.1f ms |\n",
                            1000 * Percentile(latencies, 50), 1000 * Percentile(latencies, 95),
                            1000 * Percentile(latencies, 99), 1000 * Percentile(latencies, 100))
         << absl::StrFormat(
                "| in-process solve of the same jobs p50 / p95 / p99 | %.1f / %.1f / "
                "%.1f ms |\n",
                1000 * Percentile(local_of_jobs, 50), 1000 * Percentile(local_of_jobs, 95),
                1000 * Percentile(local_of_jobs, 99))
         << absl::StrFormat(
                "| solve time in the server / in-process (sum over jobs) | %.2f s / "
                "%.2f s |\n",
                solve_total, local_total)
         << absl::StrFormat(
                "| unloaded overhead per job (latency - in-process), p50 / mean | "
                "%.2f / %.2f ms |\n",
                1000 * Percentile(sequential_overhead, 50), 1000 * Mean(sequential_overhead))
         << absl::StrFormat("| unloaded latency / in-process time, median | %.2f |\n",
                            Percentile(sequential_ratio, 50));
  if (stats.ok()) {
    report << absl::StrFormat(
        "| server: accepted / succeeded / rejected (queue full) | %d / %d / "
        "%d |\n",
        stats->accepted_total(), stats->finished_total().succeeded(),
        stats->rejected_queue_full_total());
  }
  report << absl::StrFormat("| server exit code after SIGTERM | %s |\n",
                            exit_code.has_value() ? std::to_string(*exit_code) : "still running");
  if (bounded_out) report << "\nStopped starting jobs at the time bound (--max_seconds).\n";
  for (const std::string& problem : problems) report << "\nFAILED " << problem;
  report << "\n";

  std::cout << report.str();
  if (const std::string out = absl::GetFlag(FLAGS_out); !out.empty()) {
    std::ofstream(out) << report.str();
  }
  return failures == 0 && started > 0 && exit_code == 0 ? 0 : 1;
}

}  // namespace
}  // namespace ispq::testing

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  return ispq::testing::Main();
}
