// SPDX-License-Identifier: Apache-2.0
// Load-time benchmark: for every real T-mesh, the time to parse its JSON, to parse the same
// message as binary protobuf, and to validate and build the core model; plus the problem counts
// (arcs, bundles, subproblems). Writes a TSV and prints a summary.
//
//   ispq_load_bench [--out load.tsv] [--repeat 20]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "core/mesh_stats.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/read_file.h"
#include "tests/support/test_data.h"

ABSL_FLAG(std::string, out, "load.tsv", "TSV file with one row per T-mesh");
ABSL_FLAG(int, repeat, 20, "repetitions per file; the fastest is kept");

namespace {

using Clock = std::chrono::steady_clock;

template <typename F>
double FastestSeconds(int repeat, F&& f) {
  double best = 1e300;
  for (int i = 0; i < repeat; ++i) {
    const auto start = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - start).count());
  }
  return best;
}

double Median(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  const int repeat = std::max(1, absl::GetFlag(FLAGS_repeat));
  std::ofstream out(absl::GetFlag(FLAGS_out));
  out << "model\tbytes_json\tbytes_binary\tarcs\tbundles\tsubproblems\tjson_parse_ms"
         "\tbinary_parse_ms\tvalidate_build_ms\n";
  std::vector<int> arcs, bundles, subproblems;
  size_t largest_bytes = 0;
  std::string largest_line;
  for (const std::string& file : ispq::testing::RealTMeshFiles()) {
    const std::string json = *ispq::ReadFileToString(file, ispq::kMaxTMeshFileBytes);
    const ispq::v1::TMesh proto = *ispq::ParseTMeshJson(json);
    const std::string binary = proto.SerializeAsString();
    const double json_s = FastestSeconds(repeat, [&] { (void)ispq::ParseTMeshJson(json); });
    const double binary_s = FastestSeconds(repeat, [&] { (void)ispq::ParseTMeshBinary(binary); });
    const double build_s = FastestSeconds(repeat, [&] { (void)ispq::TMeshFromProto(proto); });
    const ispq::MeshStats stats = ispq::ComputeMeshStats(*ispq::TMeshFromProto(proto));
    arcs.push_back(stats.arcs);
    bundles.push_back(stats.bundles);
    subproblems.push_back(stats.subproblems);
    char line[512];
    std::snprintf(line, sizeof(line), "%s\t%zu\t%zu\t%d\t%d\t%d\t%.3f\t%.3f\t%.3f",
                  ispq::testing::ShortName(file).c_str(), json.size(), binary.size(), stats.arcs,
                  stats.bundles, stats.subproblems, 1e3 * json_s, 1e3 * binary_s, 1e3 * build_s);
    out << line << "\n";
    if (json.size() > largest_bytes) {
      largest_bytes = json.size();
      largest_line = line;
    }
  }
  auto print_range = [](const char* name, const std::vector<int>& v) {
    std::printf("%-12s min %4d  median %6.1f  max %4d\n", name,
                *std::min_element(v.begin(), v.end()), Median(v),
                *std::max_element(v.begin(), v.end()));
  };
  std::printf("%zu T-meshes\n", arcs.size());
  print_range("arcs", arcs);
  print_range("bundles", bundles);
  print_range("subproblems", subproblems);
  std::printf(
      "largest file (model, json bytes, binary bytes, arcs, bundles, subproblems, "
      "json ms, binary ms, validate+build ms):\n  %s\n",
      largest_line.c_str());
  return 0;
}
