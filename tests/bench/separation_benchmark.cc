// SPDX-License-Identifier: Apache-2.0
// Separation-search benchmark: time per FindViolations call on every real T-mesh for two kinds
// of consistent q (near the targets, and sparse with many zero arcs, which makes many
// violations). Writes a TSV and prints a summary.
//
//   ispq_separation_bench [--out separation.tsv] [--repeat 50]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "core/separation_search.h"
#include "tests/support/consistent_quantizations.h"
#include "tests/support/test_data.h"

ABSL_FLAG(std::string, out, "separation.tsv", "TSV file with one row per T-mesh and q kind");
ABSL_FLAG(int, repeat, 50, "calls per measurement");

namespace {

std::vector<int64_t> SparseQ(const ispq::testing::ConsistentQuantizations& quantizations) {
  std::mt19937 random(5);
  std::vector<int64_t> free_values;
  for (size_t i = 0; i < quantizations.free_arcs().size(); ++i) {
    free_values.push_back(static_cast<int64_t>(random() % 2));
  }
  return quantizations.Extend(free_values);
}

}  // namespace

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  const int repeat = std::max(1, absl::GetFlag(FLAGS_repeat));
  std::ofstream out(absl::GetFlag(FLAGS_out));
  out << "model\tarcs\tq\tmicroseconds_per_call\tviolations\n";
  std::vector<double> micros_all;
  for (const std::string& file : ispq::testing::RealTMeshFiles()) {
    const ispq::TMesh mesh = ispq::testing::LoadTMeshOrDie(file);
    const ispq::testing::ConsistentQuantizations quantizations(mesh);
    ispq::SeparationSearch search(mesh);
    const std::pair<const char*, std::vector<int64_t>> inputs[] = {
        {"near_targets", quantizations.NearTargets(4.0)}, {"sparse", SparseQ(quantizations)}};
    for (const auto& [label, q] : inputs) {
      size_t found = search.FindViolations(q).size();
      const auto begin = std::chrono::steady_clock::now();
      for (int r = 0; r < repeat; ++r) found = search.FindViolations(q).size();
      const double micros =
          std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - begin)
              .count() /
          repeat;
      micros_all.push_back(micros);
      out << ispq::testing::ShortName(file) << "\t" << mesh.num_arcs() << "\t" << label << "\t"
          << micros << "\t" << found << "\n";
    }
  }
  std::sort(micros_all.begin(), micros_all.end());
  std::printf("%zu measurements: median %.1f us, max %.1f us per FindViolations call\n",
              micros_all.size(), micros_all[micros_all.size() / 2], micros_all.back());
  return 0;
}
