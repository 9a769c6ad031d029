// SPDX-License-Identifier: Apache-2.0
// One run of the scaling benchmark (run_scaling.py drives it): quantizes one T-mesh file at one
// level in-process, single-threaded, and prints one TSV row (with --header, the header first):
//
//   ispq_scaling_run --mesh F.tmesh.pb --level P [--header] [--time_limit S] [--cold_solve_memory]
//   ispq_scaling_run --mesh F.tmesh.json --stats_only [--header]
//
// Columns: arcs, level, the solve's CPU seconds in total and per phase (greedy descent,
// separation search, separating updates; CPU time of the solving thread), LP solves, separation
// rounds and rows, subproblems, objective, validity (the validator's verdict), the CPU seconds
// and objective at the first separating q (the first valid intermediate result a client gets),
// the peak resident memory (VmHWM, MiB) of the process during the solve at the end of the first
// greedy descent, at the first separating q and at the end, the peak of loading the mesh file
// before it, the CPU seconds of tracing the layered start (core/isp/parametric_layers.h) and,
// with --cold_solve_memory, the solve's own peak (-1 without, or if that second solve did not end
// with the same q). Then the mesh's statistics (MeshStatsColumns below), which say how hard the
// mesh is beside its size: blocks, critical entities (nodes, links, regions) and arcs, critical
// entities per arc and the critical arcs' share, bundles and arcs per bundle, the subproblems of
// the decomposition before the solve and the largest one's bundles, the interior singular arcs
// and whether the block frames are global (GlobalFrames below). --stats_only prints these
// alone, without solving (run_scaling.py uses it on the real T-meshes, to set the families beside
// them).
//
// The timed solve runs as `ispq quantize --local` runs it: the model is decoded from the file one
// element at a time (core/proto/tmesh_model_file.h), and the solve reuses whatever memory the
// loader freed and the process keeps. Its peak columns are the process's resident memory while it
// solves (the kernel's peak counter is reset after loading, /proc/self/clear_refs "5"), so they
// include what the loader left resident. For the solve's own
// memory, --cold_solve_memory solves a second time after returning all freed memory to the
// system (malloc_trim): every page that solve touches is its own. Timing that cold solve instead
// would count a first-touch page fault for every page (about 12 us each on the development VM),
// which no real run pays: the first separating q of a 100k-arc part took 2.1-2.5x the CPU.
#include <malloc.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "core/arc_bundles.h"
#include "core/arc_singularity.h"
#include "core/bundle_potentials.h"
#include "core/consistency_matrix.h"
#include "core/large_allocations.h"
#include "core/mesh_stats.h"
#include "core/quantization_validator.h"
#include "core/quantizer.h"
#include "core/run_clock.h"
#include "core/subproblems.h"
#include "tests/support/own_memory.h"
#include "tests/support/test_data.h"

ABSL_FLAG(std::string, mesh, "", "T-mesh file (.pb or .json)");
ABSL_FLAG(int, level, 100, "resolution level percent");
ABSL_FLAG(bool, header, false, "print the TSV header first");
ABSL_FLAG(bool, timeline, false,
          "print every progress event (CPU s, phase, sheets, LP solves) to stderr");
ABSL_FLAG(double, time_limit, std::numeric_limits<double>::infinity(), "seconds");
ABSL_FLAG(bool, cold_solve_memory, false,
          "solve again after malloc_trim to measure the solve's own peak memory");
ABSL_FLAG(bool, stats_only, false, "print the mesh's statistics only, without solving");

namespace ispq::bench {
namespace {

double StatusMib(const char* field) { return testing::OwnStatusKib(field) / 1024; }

double PeakRssMib() { return StatusMib("VmHWM:"); }

// Restarts the kernel's peak counter at the current size.
void ResetPeakRss() {
  std::ofstream clear_refs("/proc/self/clear_refs");
  clear_refs << "5";
}

// The peak resident memory of a second solve after the process returned its freed memory to the
// system: what the solve needs of its own. The solve is deterministic, so its q must be the timed
// solve's (which the validator certified); -1 if it is not.
double ColdSolvePeakRssMib(const TMesh& mesh, const QuantizeOptions& options,
                           const std::vector<int64_t>& timed_q) {
  malloc_trim(0);
  ResetPeakRss();
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  const double peak = PeakRssMib();
  if (!result.ok() || result->q != timed_q) {
    std::cerr << "the second solve did not end with the timed solve's q\n";
    return -1;
  }
  return peak;
}

// Whether the patch rotations carry every block's axes into three global axes, signs included:
// then the nodes have per-axis potentials whose differences are the arc lengths, where the part
// has no handle (core/bundle_potentials.h). Interior singular arcs break it, and so can a handle
// whose transition turns an axis around (joint-hex has no interior singular arc and fails).
bool GlobalFrames(const TMesh& mesh) { return GlobalBlockDirections(mesh).has_value(); }

// The mesh's statistics as TSV columns: a header and a row, each starting with a tab. The counts
// are `ispq stats --json`'s (core/mesh_stats.h); the largest subproblem is measured in bundles, the
// size of its LP. Computed apart from the solve, so none of it is timed.
std::pair<std::string, std::string> MeshStatsColumns(const TMesh& mesh) {
  const MeshStats s = ComputeMeshStats(mesh);
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const Subproblems subproblems(mesh, consistency, bundles);
  size_t largest = 0;
  for (int i = 0; i < subproblems.num_subproblems(); ++i) {
    largest = std::max(largest, subproblems.bundles(i).size());
  }
  // Boundary arcs marked singular are sharp edges, which turn no frame; interior ones do.
  int interior_singular_arcs = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    interior_singular_arcs += mesh.arc_singular(a) != 0 && !ArcOnBoundary(mesh, a);
  }
  const double arcs = s.arcs;
  std::ostringstream row;
  row << "\t" << s.blocks << "\t" << s.critical_entities << "\t" << s.critical_nodes << "\t"
      << s.critical_links << "\t" << s.critical_regions << "\t" << s.critical_arcs << "\t"
      << s.critical_entities / arcs << "\t" << s.critical_arcs / arcs << "\t" << s.bundles << "\t"
      << arcs / s.bundles << "\t" << s.subproblems << "\t" << largest << "\t"
      << interior_singular_arcs << "\t" << (GlobalFrames(mesh) ? 1 : 0);
  return {
      "\tblocks\tcritical_entities\tcritical_nodes\tcritical_links\tcritical_regions\t"
      "critical_arcs\tentities_per_arc\tcritical_arc_share\tbundles\tarcs_per_bundle\t"
      "mesh_subproblems\tlargest_subproblem_bundles\tinterior_singular_arcs\tglobal_frames",
      row.str()};
}

// Watches the run: memory when the first descent ends, time and objective of the first
// separating q.
class RunWatcher : public ProgressObserver {
 public:
  RunWatcher(double cpu_start, bool timeline) : cpu_start_(cpu_start), timeline_(timeline) {}
  void OnProgress(const ProgressEvent& event) override {
    const double cpu = ThreadCpuSeconds() - cpu_start_;
    if (timeline_) PrintEvent(cpu, event);
    if (event.phase == QuantizationPhase::kGreedy) {
      in_first_descent_ = greedy_rss_ < 0;
    } else if (in_first_descent_) {
      greedy_rss_ = PeakRssMib();
      in_first_descent_ = false;
    }
    if (event.separating && first_separating_cpu_ < 0) {
      first_separating_cpu_ = cpu;
      first_separating_objective_ = event.objective;
      first_separating_rss_ = PeakRssMib();
    }
  }
  double greedy_rss_ = -1;
  double first_separating_cpu_ = -1;
  double first_separating_objective_ = -1;
  double first_separating_rss_ = -1;

 private:
  static void PrintEvent(double cpu, const ProgressEvent& event) {
    std::fprintf(
        stderr, "%.3f\tphase=%d\tsheets=%lld\tround=%lld\tlp=%lld\tviolated=%lld\t%s\t%.4f\n", cpu,
        static_cast<int>(event.phase), static_cast<long long>(event.iteration),
        static_cast<long long>(event.separation_round), static_cast<long long>(event.lp_solves),
        static_cast<long long>(event.violated_constraints), event.separating ? "SEPARATING" : "-",
        event.objective);
  }

  double cpu_start_;
  bool timeline_;
  bool in_first_descent_ = false;
};

int Run() {
  const TMesh mesh = testing::LoadTMeshOrDie(absl::GetFlag(FLAGS_mesh));
  if (absl::GetFlag(FLAGS_stats_only)) {
    const auto [header, row] = MeshStatsColumns(mesh);
    if (absl::GetFlag(FLAGS_header)) std::printf("arcs%s\n", header.c_str());
    std::printf("%d%s\n", mesh.num_arcs(), row.c_str());
    return 0;
  }
  const double load_peak_rss = PeakRssMib();
  ResetPeakRss();
  double scaling = 0;
  for (const Level& level : mesh.levels()) {
    if (level.percent == absl::GetFlag(FLAGS_level)) scaling = level.scaling;
  }
  if (scaling == 0) {
    std::cerr << "no level " << absl::GetFlag(FLAGS_level) << "\n";
    return 2;
  }
  QuantizeOptions options;
  options.scaling = scaling;
  options.time_limit_seconds = absl::GetFlag(FLAGS_time_limit);
  const double cpu_start = ThreadCpuSeconds();
  RunWatcher watcher(cpu_start, absl::GetFlag(FLAGS_timeline));
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options, &watcher);
  const double cpu = ThreadCpuSeconds() - cpu_start;
  if (!result.ok()) {
    std::cerr << result.status() << "\n";
    return 1;
  }
  const double peak_rss = PeakRssMib();
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, result->q);
  const bool valid = result->valid && report.ok() && report->valid();
  const double cold_peak_rss =
      absl::GetFlag(FLAGS_cold_solve_memory) ? ColdSolvePeakRssMib(mesh, options, result->q) : -1;
  const auto [stats_header, stats_row] = MeshStatsColumns(mesh);
  if (absl::GetFlag(FLAGS_header)) {
    std::printf(
        "arcs\tlevel\tcpu_s\tgreedy_cpu_s\tsearch_cpu_s\tseparating_cpu_s\tlp_solves\t"
        "sep_rounds\tsep_rows\tsubproblems\tobjective\tvalid\ttermination\t"
        "first_separating_cpu_s\tfirst_separating_objective\tgreedy_rss_mib\t"
        "first_separating_rss_mib\tpeak_rss_mib\tload_peak_rss_mib\tlayers_cpu_s\t"
        "cold_solve_peak_rss_mib%s\n",
        stats_header.c_str());
  }
  const QuantizeStats& s = result->stats;
  std::printf(
      "%d\t%d\t%.4f\t%.4f\t%.4f\t%.4f\t%lld\t%lld\t%lld\t%d\t%.6f\t%d\t%s\t%.4f\t%.6f\t%.1f\t%."
      "1f\t%.1f\t%.1f\t%.4f\t%.1f%s\n",
      mesh.num_arcs(), absl::GetFlag(FLAGS_level), cpu, s.greedy_seconds,
      s.separation_search_seconds, s.separating_update_seconds, static_cast<long long>(s.lp_solves),
      static_cast<long long>(s.separation_rounds), static_cast<long long>(s.separation_rows),
      s.subproblems, result->objective, valid ? 1 : 0, TerminationName(result->termination),
      watcher.first_separating_cpu_, watcher.first_separating_objective_, watcher.greedy_rss_,
      watcher.first_separating_rss_, peak_rss, load_peak_rss, s.layers_seconds, cold_peak_rss,
      stats_row.c_str());
  return valid ? 0 : 3;
}

}  // namespace
}  // namespace ispq::bench

int main(int argc, char** argv) {
  ispq::MapLargeAllocationsSeparately();  // as the product's binaries do
  absl::ParseCommandLine(argc, argv);
  return ispq::bench::Run();
}
