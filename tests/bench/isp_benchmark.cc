// SPDX-License-Identifier: Apache-2.0
// The quantization benchmark: every real T-mesh at all 8 resolution levels (or some),
// single-threaded, in-process, with ISP or exact mode. Writes one TSV row per run (and, with
// --trace_out, the anytime curve of every run) and prints a one-screen summary: time (median,
// max, total), validity, objective ratios to the upstream reference (ISP and exact IQP), lower
// bounds and gaps, lcd statistics, and optionally the effect of mixed-sign sheets, of the
// reference's separation-search mode and the cost of the lower bound, measured side by side.
//
//   ispq_bench [--out bench.tsv] [--trace_out trace.tsv] [--filter SUBSTRING] [--levels 5,50]
//              [--method isp|exact] [--time_limit S] [--mixed_sign=false] [--lower_bound on]
//              [--compare_mixed_sign] [--compare_reference_search] [--compare_lower_bound]
//              [--repeat N]
//
// Not part of the unit-test run; speed and quality are measured here, never asserted in tests.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "core/quantization_validator.h"
#include "core/quantizer.h"
#include "tests/bench/progress_trace.h"
#include "tests/bench/reference_results.h"
#include "tests/support/test_data.h"

ABSL_FLAG(std::string, out, "bench.tsv", "TSV file with one row per run");
ABSL_FLAG(std::string, filter, "", "only models whose name contains this");
ABSL_FLAG(std::string, reference_dir, "",
          "directory of the reference TSVs (default: tests/data/reference)");
ABSL_FLAG(bool, compare_mixed_sign, false, "also run with mixed-sign sheets off and compare");
ABSL_FLAG(bool, compare_reference_search, false,
          "also run certifying with the reference's search alone and compare");
ABSL_FLAG(int, repeat, 1, "run each instance this many times and keep the fastest time");
ABSL_FLAG(std::string, trace_out, "", "TSV file with the anytime curve of every run");
ABSL_FLAG(std::vector<std::string>, levels, {}, "only these levels (percent), e.g. 5,50");
ABSL_FLAG(std::string, method, "isp", "isp or exact");
ABSL_FLAG(double, time_limit, 0, "time limit per run in seconds (0: none; exact mode: 60)");
ABSL_FLAG(bool, mixed_sign, true, "allow mixed-sign sheets");
ABSL_FLAG(std::string, lower_bound, "auto", "auto, on or off: the lower bound of ISP results");
ABSL_FLAG(bool, compare_lower_bound, false,
          "also time every ISP run without and with its lower bound, alternating, and compare");

namespace ispq::bench {
namespace {

struct Run {
  std::string model;
  int percent = 0;
  double scaling = 0;
  int arcs = 0;
  QuantizeResult result;
  double seconds = 0;
  bool validator_ok = false;  // independent validator call on the returned q
  std::string trace;          // TSV rows of the anytime curve
};

struct BenchConfig {
  QuantizeOptions options;
  int repeat = 1;
  std::vector<int> levels;  // empty: all
  bool trace = false;
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

const char* MethodName(const QuantizeOptions& options) {
  return options.method == QuantizationMethod::kExact ? "exact" : "isp";
}

Run RunOne(const TMesh& mesh, const std::string& model, const Level& level,
           const BenchConfig& config) {
  Run run;
  run.model = model;
  run.percent = level.percent;
  run.scaling = level.scaling;
  run.arcs = mesh.num_arcs();
  QuantizeOptions options = config.options;
  options.scaling = level.scaling;
  run.seconds = 1e300;
  for (int i = 0; i < config.repeat; ++i) {
    ProgressTrace trace;
    absl::StatusOr<QuantizeResult> result =
        Quantize(mesh, options, config.trace ? &trace : nullptr);
    if (!result.ok()) {
      std::cerr << model << " @" << level.percent << "%: " << result.status() << "\n";
      run.seconds = 0;
      return run;
    }
    if (result->stats.solve_seconds < run.seconds && config.trace) {
      std::ostringstream rows;
      rows.precision(10);
      trace.WriteRows(model, level.percent, MethodName(options), rows);
      run.trace = rows.str();
    }
    run.seconds = std::min(run.seconds, result->stats.solve_seconds);
    run.result = *std::move(result);
  }
  ValidationOptions validation;
  validation.separation = options.separation;
  const absl::StatusOr<ValidationReport> report =
      ValidateQuantization(mesh, run.result.q, validation);
  run.validator_ok = report.ok() && report->valid();
  return run;
}

bool Selected(const BenchConfig& config, int percent) {
  return config.levels.empty() ||
         std::find(config.levels.begin(), config.levels.end(), percent) != config.levels.end();
}

// Runs every model at every selected level.
std::vector<Run> RunAll(const std::vector<std::string>& files, const BenchConfig& config) {
  std::vector<Run> runs;
  for (const std::string& file : files) {
    const TMesh mesh = testing::LoadTMeshOrDie(file);
    const std::string model = testing::ShortName(file);
    for (const Level& level : mesh.levels()) {
      if (Selected(config, level.percent)) runs.push_back(RunOne(mesh, model, level, config));
    }
  }
  return runs;
}

// A fingerprint of q (FNV-1a over the values), so that two TSVs show whether every q is equal.
uint64_t QHash(const std::vector<int64_t>& q) {
  uint64_t h = 1469598103934665603ull;
  for (int64_t x : q) h = (h ^ static_cast<uint64_t>(x)) * 1099511628211ull;
  return h;
}

std::string Optional(const std::optional<double>& value) {
  return value.has_value() ? std::to_string(*value) : "";
}

void WriteTsv(const std::string& path, const std::vector<Run>& runs,
              const ReferenceResults& reference) {
  std::ofstream out(path);
  out.precision(10);
  out << "model\tlevel\tscaling\tarcs\tmethod\ttime_s\tobjective\tlower_bound\tgap\ttermination"
         "\thexes\tlp_solves\tsep_rounds\tsep_rows\tlcd_one\tlcd_two\tlcd_more\tbound_s"
         "\tmilp_solves\tmilp_nodes\tmilp_incumbents\texact_s\tvalid\tref_time_s\tref_objective"
         "\tiqp_time_s\tiqp_objective\tq_hash\n";
  for (const Run& r : runs) {
    const auto ref = reference.Isp(r.model, r.percent);
    const auto iqp = reference.Iqp(r.model, r.percent);
    const QuantizeStats& s = r.result.stats;
    out << r.model << "\t" << r.percent << "\t" << r.scaling << "\t" << r.arcs << "\t"
        << (s.milp_solves > 0 || r.result.termination == Termination::kOptimal ? "exact" : "isp")
        << "\t" << r.seconds << "\t" << r.result.objective << "\t" << Optional(r.result.lower_bound)
        << "\t" << Optional(r.result.gap) << "\t" << TerminationName(r.result.termination) << "\t"
        << r.result.hexes << "\t" << s.lp_solves << "\t" << s.separation_rounds << "\t"
        << s.separation_rows << "\t" << s.lcd_one << "\t" << s.lcd_two << "\t" << s.lcd_more << "\t"
        << s.lower_bound_seconds << "\t" << s.milp_solves << "\t" << s.milp_nodes << "\t"
        << s.milp_incumbents << "\t" << s.exact_seconds << "\t"
        << (r.result.valid && r.validator_ok ? "yes" : "no") << "\t"
        << (ref ? std::to_string(ref->seconds) : "") << "\t"
        << (ref ? std::to_string(ref->objective) : "") << "\t"
        << (iqp ? std::to_string(iqp->seconds) : "") << "\t"
        << (iqp ? std::to_string(iqp->objective) : "") << "\t" << QHash(r.result.q) << "\n";
  }
}

void WriteTrace(const std::string& path, const std::vector<Run>& runs) {
  std::ofstream out(path);
  out.precision(10);
  ProgressTrace::WriteHeader(out);
  for (const Run& r : runs) out << r.trace;
}

// Objective ratio that tolerates zero objectives on both sides.
double Ratio(double ours, double theirs) {
  if (theirs <= 1e-9) return ours <= 1e-9 ? 1.0 : ours / 1e-9;
  return ours / theirs;
}

void PrintTimes(const std::vector<Run>& runs, const ReferenceResults& reference) {
  std::vector<double> times, ref_times;
  int valid = 0;
  QuantizeStats total;
  for (const Run& r : runs) {
    times.push_back(r.seconds);
    valid += r.result.valid && r.validator_ok;
    total.lcd_one += r.result.stats.lcd_one;
    total.lcd_two += r.result.stats.lcd_two;
    total.lcd_more += r.result.stats.lcd_more;
    total.lp_solves += r.result.stats.lp_solves;
    if (auto ref = reference.Isp(r.model, r.percent)) ref_times.push_back(ref->seconds);
  }
  const double sum = std::accumulate(times.begin(), times.end(), 0.0);
  const double ref_sum = std::accumulate(ref_times.begin(), ref_times.end(), 0.0);
  std::printf("runs %zu, valid %d, invalid %zu\n", runs.size(), valid, runs.size() - valid);
  std::printf(
      "time: median %.4f s, max %.4f s, total %.2f s   (reference ISP: median %.4f s, total %.2f "
      "s)\n",
      Median(times), times.empty() ? 0 : *std::max_element(times.begin(), times.end()), sum,
      Median(ref_times), ref_sum);
  std::printf("LP solves %lld; lcd of rational LP solutions: 1: %lld, 2: %lld, >2: %lld\n",
              static_cast<long long>(total.lp_solves), static_cast<long long>(total.lcd_one),
              static_cast<long long>(total.lcd_two), static_cast<long long>(total.lcd_more));
}

// Gaps of the runs that have a lower bound, and how many are proven optimal.
void PrintGaps(const std::vector<Run>& runs) {
  std::vector<double> gaps;
  int optimal = 0, zero = 0;
  for (const Run& r : runs) {
    optimal += r.result.termination == Termination::kOptimal;
    if (!r.result.gap.has_value()) continue;
    gaps.push_back(*r.result.gap);
    zero += *r.result.gap <= 1e-9;
  }
  if (gaps.empty()) return;
  std::printf(
      "lower bounds on %zu runs: gap median %.4f%%, mean %.4f%%, max %.4f%%, zero on %d; "
      "proven optimal %d\n",
      gaps.size(), 100 * Median(gaps),
      100 * std::accumulate(gaps.begin(), gaps.end(), 0.0) / static_cast<double>(gaps.size()),
      100 * *std::max_element(gaps.begin(), gaps.end()), zero, optimal);
}

void PrintLevels(const std::vector<Run>& runs, const ReferenceResults& reference) {
  std::printf("\n%-6s %5s %12s %12s %12s %6s %6s %10s\n", "level", "runs", "mean ratio",
              "sum ratio", "vs IQP", "better", "worse", "median s");
  for (int percent : {0, 1, 5, 10, 17, 25, 50, 100}) {
    std::vector<double> ratios, level_times, iqp_ratios;
    double ours_sum = 0, ref_sum_level = 0;
    int better = 0, worse = 0;
    for (const Run& r : runs) {
      if (r.percent != percent) continue;
      level_times.push_back(r.seconds);
      if (auto ref = reference.Isp(r.model, percent)) {
        ratios.push_back(Ratio(r.result.objective, ref->objective));
        ours_sum += r.result.objective;
        ref_sum_level += ref->objective;
        better += r.result.objective < ref->objective * (1 - 1e-6) - 1e-9;
        worse += r.result.objective > ref->objective * (1 + 1e-6) + 1e-9;
      }
      if (auto iqp = reference.Iqp(r.model, percent))
        iqp_ratios.push_back(Ratio(r.result.objective, iqp->objective));
    }
    if (level_times.empty()) continue;
    const double mean =
        ratios.empty() ? 0 : std::accumulate(ratios.begin(), ratios.end(), 0.0) / ratios.size();
    const double iqp_mean =
        iqp_ratios.empty()
            ? 0
            : std::accumulate(iqp_ratios.begin(), iqp_ratios.end(), 0.0) / iqp_ratios.size();
    std::printf("%-6d %5zu %12.4f %12.4f %12s %6d %6d %10.4f\n", percent, level_times.size(), mean,
                ref_sum_level > 0 ? ours_sum / ref_sum_level : 0.0,
                iqp_ratios.empty() ? "-" : std::to_string(iqp_mean).c_str(), better, worse,
                Median(level_times));
  }
}

// Against the reference IQP, instance by instance: how many are not worse.
void PrintIqpComparison(const std::vector<Run>& runs, const ReferenceResults& reference) {
  int n = 0, not_worse = 0, better = 0;
  for (const Run& r : runs) {
    const auto iqp = reference.Iqp(r.model, r.percent);
    if (!iqp.has_value()) continue;
    ++n;
    not_worse += r.result.objective <= iqp->objective * (1 + 1e-6) + 1e-9;
    better += r.result.objective < iqp->objective * (1 - 1e-6) - 1e-9;
  }
  if (n > 0) {
    std::printf("vs reference IQP on %d instances: not worse on %d, better on %d\n", n, not_worse,
                better);
  }
}

void PrintSummary(const std::vector<Run>& runs, const ReferenceResults& reference) {
  PrintTimes(runs, reference);
  PrintGaps(runs);
  PrintIqpComparison(runs, reference);
  PrintLevels(runs, reference);
}

// Counts instances where variant A's objective is lower than B's by more than `margin`.
void PrintComparison(const char* name_a, const std::vector<Run>& a, const char* name_b,
                     const std::vector<Run>& b) {
  int a_better = 0, b_better = 0, a_much_better = 0, n = 0;
  double best_factor = 1;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    if (!(a[i].result.valid && b[i].result.valid)) continue;
    ++n;
    const double oa = a[i].result.objective, ob = b[i].result.objective;
    a_better += oa < ob * (1 - 1e-6);
    b_better += ob < oa * (1 - 1e-6);
    a_much_better += oa < ob * 0.95;
    if (oa > 1e-9) best_factor = std::max(best_factor, ob / oa);
  }
  std::printf(
      "\n%s vs %s over %d valid pairs: %s better in %d (by >5%%: %d), worse in %d; "
      "best-case factor %.2f\n",
      name_a, name_b, n, name_a, a_better, a_much_better, b_better, best_factor);
}

// ISP without and with its lower bound, alternating per instance so that both see the same
// machine load; the fastest of `repeat` runs each.
void CompareLowerBound(const std::vector<std::string>& files, BenchConfig config) {
  double without = 0, with = 0, bound_only = 0;
  std::vector<double> ratios;
  for (const std::string& file : files) {
    const TMesh mesh = testing::LoadTMeshOrDie(file);
    for (const Level& level : mesh.levels()) {
      if (!Selected(config, level.percent)) continue;
      config.options.lower_bound = LowerBoundMode::kNever;
      const Run off = RunOne(mesh, "", level, config);
      config.options.lower_bound = LowerBoundMode::kAlways;
      const Run on = RunOne(mesh, "", level, config);
      without += off.seconds;
      with += on.seconds;
      bound_only += on.result.stats.lower_bound_seconds;
      if (off.seconds > 0) ratios.push_back(on.seconds / off.seconds);
    }
  }
  std::printf(
      "\nlower bound cost, side by side over %zu runs: ISP alone %.3f s, ISP with bound %.3f s "
      "(ratio %.3f; bound LPs %.3f s); per-run ratio median %.3f\n",
      ratios.size(), without, with, without > 0 ? with / without : 0, bound_only, Median(ratios));
}

absl::StatusOr<BenchConfig> ConfigFromFlags() {
  BenchConfig config;
  config.repeat = std::max(1, absl::GetFlag(FLAGS_repeat));
  config.trace = !absl::GetFlag(FLAGS_trace_out).empty();
  for (const std::string& level : absl::GetFlag(FLAGS_levels)) {
    int percent = 0;
    if (!absl::SimpleAtoi(level, &percent)) return absl::InvalidArgumentError("bad --levels");
    config.levels.push_back(percent);
  }
  const std::string method = absl::GetFlag(FLAGS_method);
  if (method != "isp" && method != "exact") return absl::InvalidArgumentError("bad --method");
  config.options.method = method == "exact" ? QuantizationMethod::kExact : QuantizationMethod::kIsp;
  const std::string bound = absl::GetFlag(FLAGS_lower_bound);
  if (bound == "on") config.options.lower_bound = LowerBoundMode::kAlways;
  if (bound == "off") config.options.lower_bound = LowerBoundMode::kNever;
  if (absl::GetFlag(FLAGS_time_limit) > 0) {
    config.options.time_limit_seconds = absl::GetFlag(FLAGS_time_limit);
  }
  config.options.mixed_sign = absl::GetFlag(FLAGS_mixed_sign);
  return config;
}

}  // namespace
}  // namespace ispq::bench

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  using namespace ispq;
  std::vector<std::string> files;
  for (const std::string& f : testing::RealTMeshFiles()) {
    if (absl::StrContains(f, absl::GetFlag(FLAGS_filter))) files.push_back(f);
  }
  if (files.empty()) {
    std::cerr << "no T-meshes found under " << testing::RealTMeshDir() << "\n";
    return 1;
  }
  absl::StatusOr<bench::BenchConfig> config = bench::ConfigFromFlags();
  if (!config.ok()) {
    std::cerr << config.status().message() << "\n";
    return 2;
  }
  std::string reference_dir = absl::GetFlag(FLAGS_reference_dir);
  if (reference_dir.empty()) reference_dir = testing::ReferenceResultsDir();
  const bench::ReferenceResults reference = bench::ReferenceResults::Load(reference_dir);

  const std::vector<bench::Run> runs = bench::RunAll(files, *config);
  bench::WriteTsv(absl::GetFlag(FLAGS_out), runs, reference);
  if (config->trace) bench::WriteTrace(absl::GetFlag(FLAGS_trace_out), runs);
  bench::PrintSummary(runs, reference);
  if (absl::GetFlag(FLAGS_compare_mixed_sign)) {
    bench::BenchConfig uniform = *config;
    uniform.options.mixed_sign = false;
    uniform.repeat = 1;
    uniform.trace = false;
    bench::PrintComparison("mixed-sign", runs, "uniform-sign", bench::RunAll(files, uniform));
  }
  if (absl::GetFlag(FLAGS_compare_reference_search)) {
    bench::BenchConfig compat = *config;
    compat.options.separation = SeparationRule::kReferenceSearch;
    compat.repeat = 1;
    compat.trace = false;
    const std::vector<bench::Run> compat_runs = bench::RunAll(files, compat);
    int64_t rows_sorted = 0, rows_compat = 0;
    for (const auto& r : runs) rows_sorted += r.result.stats.separation_rows;
    for (const auto& r : compat_runs) rows_compat += r.result.stats.separation_rows;
    std::printf("\nseparation rows found: both searches %lld, reference search only %lld\n",
                static_cast<long long>(rows_sorted), static_cast<long long>(rows_compat));
    bench::PrintComparison("both searches", runs, "reference only", compat_runs);
  }
  if (absl::GetFlag(FLAGS_compare_lower_bound)) bench::CompareLowerBound(files, *config);
  int invalid = 0;
  for (const auto& r : runs) invalid += !(r.result.valid && r.validator_ok);
  return invalid == 0 ? 0 : 1;
}
