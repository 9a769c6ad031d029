// SPDX-License-Identifier: Apache-2.0
// The memory a solve needs, against the server's estimate of it (server/memory/memory_estimates.h):
// quantizes T-mesh files at some levels with either method, in-process, and prints one TSV row per
// run:
//
//   ispq_solve_memory_bench [--real] [--meshes A.tmesh.json,B.pb] [--levels 5,25,100 | --scaling S]
//                           [--methods isp,exact] [--copies K] [--decompose=false]
//                           [--lower_bound auto|on|off] [--time_limit S] [--rss]
//
// --real takes every real T-mesh (tests/data/tmesh), --meshes any T-mesh files (JSON or binary
// ispq.v1.TMesh); --copies K solves K disjoint copies of each mesh (tests/support/tmesh_copies.h):
// as many independent subproblems, each with an LP of its own.
//
// Columns: mesh, arcs, bundles, subproblems (as admission counts them), level (0 with --scaling),
// method, termination, the peak of live heap bytes above the level before the call
// (tests/support/heap_peak.h: every allocation of every library, by usable size) in total and per
// arc, the estimate SolverBytes() for the job and the ratio estimate / peak. With --rss also the
// resident set's growth during a second, cold solve (after malloc_trim, the kernel's peak counter
// reset): what the solve costs the process in touched pages, less than the heap where allocations
// are never written in full (the LP factorizations' work areas), more where the allocator's slack
// and page granularity show (0.2-1.2 times the heap peak). Then the solve's wall seconds and
// those of its lower bound, and a fingerprint of q, equal across builds that found the same
// answer (a change meant to save memory must change no answer).
//
// server/memory/memory_estimates.h was calibrated with (D=tests/data/tmesh/hex-me):
//   --real --rss
//   --meshes $D/s01c_cube.tmesh.json --copies 1000 (and 8000) --levels 25 --rss
//   --meshes $D/{s07c_notch,s01b_cube,n09c_pyramid,s13u_cube_rounded_2}.tmesh.json --copies 1000
//   --meshes <the femur shell of tests/data/tmesh/metamesh-guided-hexalab> --copies 200
//   --meshes $D/{s01c_cube,s01b_cube,s07c_notch}.tmesh.json --copies 300 --decompose=false
//   --meshes of ispq_make_large_tmesh --family single|assembly50|assembly16 --arcs 30000, and
//            single at 100000 arcs, --rss; assembly16 at 100000 arcs at level 5
//
// The observer plays the server's part (server/jobs/progress_publisher.h): it asks for q at every
// event and keeps the latest as 32-bit integers, as a job keeps its latest intermediate result.
#include <malloc.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "core/large_allocations.h"
#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "core/quantizer.h"
#include "core/resolution_levels.h"
#include "server/memory/memory_estimates.h"
#include "tests/support/heap_peak.h"
#include "tests/support/own_memory.h"
#include "tests/support/test_data.h"
#include "tests/support/tmesh_copies.h"

ABSL_FLAG(bool, real, false, "every real T-mesh (tests/data/tmesh)");
ABSL_FLAG(std::string, meshes, "", "comma-separated T-mesh files (.pb or .json)");
ABSL_FLAG(std::string, levels, "5,25,100", "resolution levels, percent");
ABSL_FLAG(double, scaling, 0, "a scaling factor instead of the levels");
ABSL_FLAG(std::string, methods, "isp", "isp, exact or both (comma-separated)");
ABSL_FLAG(bool, rss, false, "also measure the resident set's growth in a cold second solve");
ABSL_FLAG(double, time_limit, -1, "seconds (default: the method's default)");
ABSL_FLAG(int, copies, 1, "solve this many disjoint copies of each mesh");
ABSL_FLAG(std::string, lower_bound, "auto", "auto, on or off");
ABSL_FLAG(bool, decompose, true, "one LP per independent subproblem (false: one LP in all)");

namespace ispq::bench {
namespace {

// Keeps the latest q as a job keeps its latest intermediate quantization.
class ServerLikeObserver : public ProgressObserver {
 public:
  void OnProgress(const ProgressEvent& event) override {
    if (event.q.empty()) return;
    latest_.assign(event.q.begin(), event.q.end());
  }
  bool WantsQuantization() const override { return true; }

 private:
  std::vector<int32_t> latest_;
};

// The resident set's growth over a solve that starts with every freed page returned.
int64_t ColdRssGrowthBytes(const TMesh& mesh, const QuantizeOptions& options) {
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
  const double before_kib = testing::OwnStatusKib("VmRSS:");
  ServerLikeObserver observer;
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options, &observer);
  if (!result.ok()) return -1;
  return static_cast<int64_t>((testing::OwnStatusKib("VmHWM:") - before_kib) * 1024);
}

struct Run {
  Termination termination = Termination::kConverged;
  int64_t heap_peak = 0;
  QuantizeStats stats;
  uint64_t q_fingerprint = 0;
};

// FNV-1a over q: equal across runs that found the same answer, to check that a change meant to
// save memory changed no answer.
uint64_t Fingerprint(const std::vector<int64_t>& q) {
  uint64_t hash = 14695981039346656037ull;
  for (int64_t value : q) {
    for (int byte = 0; byte < 8; ++byte) {
      hash ^= static_cast<uint64_t>(value >> (8 * byte)) & 0xff;
      hash *= 1099511628211ull;
    }
  }
  return hash;
}

absl::StatusOr<Run> MeasureHeapPeak(const TMesh& mesh, const QuantizeOptions& options) {
  ServerLikeObserver observer;
  testing::HeapPeakScope scope;
  absl::StatusOr<QuantizeResult> result = Quantize(mesh, options, &observer);
  const int64_t peak = scope.PeakBytes();
  if (!result.ok()) return result.status();
  return Run{result->termination, peak, result->stats, Fingerprint(result->q)};
}

std::vector<int> Levels() {
  std::vector<int> levels;
  for (absl::string_view text : absl::StrSplit(absl::GetFlag(FLAGS_levels), ',')) {
    int level = 0;
    if (absl::SimpleAtoi(text, &level)) levels.push_back(level);
  }
  return levels;
}

std::vector<std::string> MeshFiles() {
  std::vector<std::string> files;
  if (absl::GetFlag(FLAGS_real)) files = testing::RealTMeshFiles();
  for (absl::string_view file :
       absl::StrSplit(absl::GetFlag(FLAGS_meshes), ',', absl::SkipEmpty())) {
    files.emplace_back(file);
  }
  return files;
}

TMesh LoadMesh(const std::string& file) {
  const int copies = absl::GetFlag(FLAGS_copies);
  if (copies <= 1) return testing::LoadTMeshOrDie(file);
  return testing::TMeshOrDie(testing::DisjointCopies(testing::LoadProtoOrDie(file), copies));
}

// The level's scaling as the file gives it, else computed (copies drop the levels).
double ScalingOf(const TMesh& mesh, int level) {
  for (const Level& l : mesh.levels()) {
    if (l.percent == level) return l.scaling;
  }
  return ScalingForPercent(mesh.arc_lengths(), level).value_or(0);
}

std::string Name(const std::string& file) {
  const int copies = absl::GetFlag(FLAGS_copies);
  const std::string name = absl::EndsWith(file, ".tmesh.json") ? testing::ShortName(file) : file;
  return copies > 1 ? absl::StrCat(name, "x", copies) : name;
}

void MeasureMesh(const std::string& file) {
  const TMesh mesh = LoadMesh(file);
  // As admission computes them (server/model/mesh_admission.cc).
  const v1::MeshStats stats = MeshStatsToProto(ComputeMeshStats(mesh));
  for (absl::string_view method_name : absl::StrSplit(absl::GetFlag(FLAGS_methods), ',')) {
    const bool exact = method_name == "exact";
    const double factor = absl::GetFlag(FLAGS_scaling);
    for (int level : factor > 0 ? std::vector<int>{0} : Levels()) {
      QuantizeOptions options;
      options.scaling = factor > 0 ? factor : ScalingOf(mesh, level);
      if (options.scaling == 0) continue;
      options.method = exact ? QuantizationMethod::kExact : QuantizationMethod::kIsp;
      options.decompose = absl::GetFlag(FLAGS_decompose);
      const std::string bound = absl::GetFlag(FLAGS_lower_bound);
      if (bound == "on") options.lower_bound = LowerBoundMode::kAlways;
      if (bound == "off") options.lower_bound = LowerBoundMode::kNever;
      if (absl::GetFlag(FLAGS_time_limit) >= 0) {
        options.time_limit_seconds = absl::GetFlag(FLAGS_time_limit);
      }
      const absl::StatusOr<Run> run = MeasureHeapPeak(mesh, options);
      if (!run.ok()) {
        std::cerr << file << " level " << level << ": " << run.status() << "\n";
        continue;
      }
      const server::SolveSize size = server::SolveSizeOf(stats, options);
      const int64_t estimate = server::SolverBytes(size);
      const int64_t rss = absl::GetFlag(FLAGS_rss) ? ColdRssGrowthBytes(mesh, options) : -1;
      std::printf(
          "%s\t%d\t%d\t%d\t%d\t%s\t%s\t%lld\t%.1f\t%lld\t%.2f\t%lld\t%.4f\t%.4f\t%016llx\n",
          Name(file).c_str(), mesh.num_arcs(), stats.bundles(), static_cast<int>(size.subproblems),
          level, exact ? "exact" : "isp", TerminationName(run->termination),
          static_cast<long long>(run->heap_peak),
          static_cast<double>(run->heap_peak) / mesh.num_arcs(), static_cast<long long>(estimate),
          static_cast<double>(estimate) / static_cast<double>(run->heap_peak),
          static_cast<long long>(rss), run->stats.solve_seconds, run->stats.lower_bound_seconds,
          static_cast<unsigned long long>(run->q_fingerprint));
      std::fflush(stdout);
    }
  }
}

int Run() {
  if (!testing::HeapCountingActive()) {
    std::cerr << "the counting malloc is not in effect\n";
    return 1;
  }
  std::printf(
      "mesh\tarcs\tbundles\tsubproblems\tlevel\tmethod\ttermination\theap_peak_bytes\theap_peak_"
      "per_arc\t"
      "estimate_bytes\testimate_over_peak\tcold_rss_growth_bytes\tsolve_s\tlower_bound_s\tq_"
      "fingerprint\n");
  for (const std::string& file : MeshFiles()) MeasureMesh(file);
  return 0;
}

}  // namespace
}  // namespace ispq::bench

int main(int argc, char** argv) {
  ispq::MapLargeAllocationsSeparately();  // as the product's binaries do
  absl::ParseCommandLine(argc, argv);
  return ispq::bench::Run();
}
