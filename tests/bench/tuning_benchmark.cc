// SPDX-License-Identifier: Apache-2.0
// The effect of each choice of the ISP engine's tuning (core/isp/isp_tuning.h): every real
// T-mesh at all 8 levels with the defaults, then with one choice switched back at a time, each
// result checked by the validator. Prints, per variant, the mean and total objective ratio to the
// reference ISP results, the change from the defaults, LP solves and CPU time; the comments in
// isp_tuning.h quote these numbers.
//
//   ispq_tuning_bench [--filter SUBSTRING]
#include <cstdio>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/strings/match.h"
#include "core/isp/clp_sheet_lp.h"
#include "core/isp/integer_sheet_pump.h"
#include "core/quantization_validator.h"
#include "tests/bench/reference_results.h"
#include "tests/support/test_data.h"

ABSL_FLAG(std::string, filter, "", "only models whose name contains this");
ABSL_FLAG(std::string, reference_dir, "",
          "directory of the reference TSVs (default: tests/data/reference)");

namespace ispq::bench {
namespace {

struct Variant {
  std::string name;
  std::function<void(IspTuning&)> apply;
};

struct Totals {
  double ratio_sum = 0;
  double objective = 0;
  double reference_objective = 0;
  int runs = 0;
  int invalid = 0;
  int64_t lp_solves = 0;
  double cpu_seconds = 0;
};

double Objective(const TMesh& mesh, double scaling, const std::vector<int64_t>& q) {
  double sum = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const double d = static_cast<double>(q[a]) - scaling * mesh.arc_length(a);
    sum += d * d;
  }
  return sum;
}

Totals RunVariant(const Variant& variant, const std::vector<std::string>& files,
                  const ReferenceResults& reference) {
  IspTuning tuning;
  variant.apply(tuning);
  Totals totals;
  for (const std::string& file : files) {
    const TMesh mesh = testing::LoadTMeshOrDie(file);
    for (const Level& level : mesh.levels()) {
      const auto ref = reference.Isp(testing::ShortName(file), level.percent);
      if (!ref.has_value()) continue;
      QuantizeOptions options;
      options.scaling = level.scaling;
      const std::clock_t start = std::clock();
      const absl::StatusOr<IspOutcome> outcome =
          RunIntegerSheetPump(mesh, options, ClpSheetLpFactory(), tuning, nullptr, nullptr);
      totals.cpu_seconds += static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
      const absl::StatusOr<ValidationReport> report =
          outcome.ok() ? ValidateQuantization(mesh, outcome->q) : outcome.status();
      if (!report.ok() || !report->valid()) {
        ++totals.invalid;
        continue;
      }
      const double objective = Objective(mesh, level.scaling, outcome->q);
      totals.ratio_sum += ref->objective > 1e-9 ? objective / ref->objective : 1.0;
      totals.objective += objective;
      totals.reference_objective += ref->objective;
      totals.lp_solves += outcome->stats.lp_solves;
      ++totals.runs;
    }
  }
  return totals;
}

int Run() {
  const std::string dir = absl::GetFlag(FLAGS_reference_dir).empty()
                              ? testing::ReferenceResultsDir()
                              : absl::GetFlag(FLAGS_reference_dir);
  const ReferenceResults reference = ReferenceResults::Load(dir);
  std::vector<std::string> files;
  for (const std::string& f : testing::RealTMeshFiles()) {
    if (absl::StrContains(f, absl::GetFlag(FLAGS_filter))) files.push_back(f);
  }
  const std::vector<Variant> variants = {
      {"defaults", [](IspTuning&) {}},
      {"repair_attempts=0", [](IspTuning& t) { t.repair_attempts = 0; }},
      {"integer_dive=false", [](IspTuning& t) { t.integer_dive = false; }},
      {"failsafe_separation_only=true", [](IspTuning& t) { t.failsafe_separation_only = true; }},
      {"thorough_final_pass=false", [](IspTuning& t) { t.thorough_final_pass = false; }},
      {"max_new_rows_per_search=all", [](IspTuning& t) { t.max_new_rows_per_search = 1 << 30; }},
      {"max_new_rows_per_search=1", [](IspTuning& t) { t.max_new_rows_per_search = 1; }},
      {"away_checks_max_bundles=0", [](IspTuning& t) { t.away_checks_max_bundles = 0; }},
      {"layered_start_min_arcs=0", [](IspTuning& t) { t.layered_start_min_arcs = 0; }},
  };
  std::printf("%-36s %5s %7s %10s %10s %9s %10s %8s\n", "variant", "runs", "invalid", "mean ratio",
              "sum ratio", "vs dflt", "LP solves", "cpu s");
  double default_mean = 0;
  int invalid = 0;
  for (const Variant& v : variants) {
    const Totals t = RunVariant(v, files, reference);
    const double mean = t.runs ? t.ratio_sum / t.runs : 0;
    if (v.name == "defaults") default_mean = mean;
    invalid += t.invalid;
    std::printf("%-36s %5d %7d %10.6f %10.6f %+8.3f%% %10lld %8.2f\n", v.name.c_str(), t.runs,
                t.invalid, mean,
                t.reference_objective > 0 ? t.objective / t.reference_objective : 0,
                default_mean > 0 ? 100 * (mean / default_mean - 1) : 0,
                static_cast<long long>(t.lp_solves), t.cpu_seconds);
  }
  return invalid == 0 ? 0 : 1;
}

}  // namespace
}  // namespace ispq::bench

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  return ispq::bench::Run();
}
