// SPDX-License-Identifier: Apache-2.0
// The memory budget's estimates (server/memory/memory_budget.h) of what meshes, jobs and results
// hold.
//
// A validated core TMesh takes 1.2-1.7 times the size of its binary protobuf; a retained result
// is its q (4 bytes per arc) and a few small messages.
//
// The solver's working memory, held while a job is queued or runs, is estimated from what
// admission knows (the admitted mesh's stats and the job's options, SolveSizeOf):
//
//   kSolverBaseBytes + kSolverBytesPerArc * arcs + kSolverBytesPerBundle * bundles
//     + min(kLpMaxBytes * subproblems, kLpBaseBytes * subproblems + kLpBytesPerBundle * bundles)
//     + (exact mode only) kExactBaseBytes + kExactBytesPerArc * arcs
//
// calibrated on the peak of live heap bytes of in-process solves (every allocation of every
// library, by usable size: tests/bench/solve_memory_benchmark.cc, 225 ISP runs at levels 5, 25
// and 100), which tests/server/memory/solver_memory_test.cc holds it to:
//   * Arcs and bundles: the mesh's tables, the separation search, the rows, the LP columns, and
//     CLP's copy of an LP when a solve goes to CLP (on LPs of 4000 columns or more, every new
//     objective does). Single parts of 30k and 100k arcs take 1.02-1.15 KB per arc,
//     feature-dense assemblies of 30k-300k arcs took 1.51-2.22 KB per arc before their LPs
//     without a root became flows (core/isp/sheet_network.h: no CLP copies; 1.24 KB per arc at
//     20k), one LP over 300 disjoint copies (decomposition off) 0.94-2.46 KB per arc. Admission
//     cannot tell which meshes get flows, so the per-bundle term still covers the copies: 8 KiB
//     per bundle (was 10) keeps 1.02 times the 2.22 KB per arc of the densest assembly measured
//     on the LP path and brings the flow assembly of the test to 1.90 times its peak.
//   * One LP per independent subproblem (one in all without decomposition). Its fixed part is
//     its vectors of max_pivots entries and its factorization's room for updates, which grows
//     with its rows up to about 430 KB at 20 rows (core/isp/sparse_dual_simplex.cc). 1000
//     copies of meshes whose subproblems have 1-2 bundles take 67-97 KB per subproblem (s01b,
//     s01c, s07c), of meshes with 10-33 bundles per subproblem 460-790 KB (femur shell, n09c,
//     s13u). An LP is counted at kLpBaseBytes plus kLpBytesPerBundle per bundle, at most
//     kLpMaxBytes; summed over the subproblems that is at most the min() above, however the
//     bundles are shared out.
//   * What every solve has: 0.32 MB for the 12-arc cube, up to 1.8 MB on the real meshes.
// Estimate over measured peak (at 10 KiB per bundle): 1.15-1.88 on the 30k-300k-arc parts (2.1 on
// a sparser 20k-arc single part at levels 5 and 25), 1.17-2.97 on the 62 real meshes (each below
// 2 MB; 11 of 186 runs above 2), and, measured with 1 KiB per arc, 1.11-2.03 on 200-8000 disjoint
// copies and 1.10-2.58 on one LP over copies. At 8 KiB per bundle the test's runs are 1.13-1.90
// (single 30k 1.56-1.69, assembly 20k with flows 1.90, 100 pyramids 1.13). 896 bytes per arc since
// the separation search stopped reading the tables of the starts it settles without a walk: a
// 30k-arc single part's peak fell 5-12 %, to 2.01 times the 1 KiB estimate. The large parts' peaks
// rose 15-30% when new objectives on large LPs went to CLP at once: the estimate follows the
// solver, and the test says when it no longer does. The cold resident-set growth is 0.2-1.2 times
// the heap peak: much of an LP's room is allocated but never written, which a long-running server's
// allocator does not promise. Exact mode adds CBC's branch and bound: up to 15 MB on real meshes of
// 300 arcs and 23 KB per arc on a 30k-arc assembly (697 MB, optimal after 33 s); its tree grows
// with the time it runs, so those two terms are a margin over what was seen rather than a bound.
#ifndef ISPQ_SERVER_MEMORY_MEMORY_ESTIMATES_H_
#define ISPQ_SERVER_MEMORY_MEMORY_ESTIMATES_H_

#include <cstdint>

#include "core/quantize_options.h"
#include "ispq/v1/mesh_stats.pb.h"
#include "ispq/v1/quantization.pb.h"

namespace ispq::server {

inline constexpr int64_t kSolverBaseBytes = 128 << 10;
inline constexpr int64_t kSolverBytesPerArc = 896;
inline constexpr int64_t kSolverBytesPerBundle = 8 << 10;
inline constexpr int64_t kLpBaseBytes = 64 << 10;
inline constexpr int64_t kLpBytesPerBundle = 40 << 10;
inline constexpr int64_t kLpMaxBytes = 448 << 10;
inline constexpr int64_t kExactBaseBytes = 16 << 20;
inline constexpr int64_t kExactBytesPerArc = 32 << 10;
// A job's own objects (its events, names, options) besides mesh and result.
inline constexpr int64_t kJobOverheadBytes = 8 << 10;

// The core TMesh validated from a mesh of `wire_bytes` binary protobuf bytes.
inline int64_t MeshBytes(int64_t wire_bytes) { return 2 * wire_bytes + kJobOverheadBytes; }

// What the solver's working memory depends on.
struct SolveSize {
  int64_t arcs = 0;
  int64_t bundles = 0;
  int64_t subproblems = 0;  // the LPs the solve keeps
  bool exact = false;       // exact mode: CBC after ISP
};

// From the mesh's stats as admission computed them and the job's resolved options: one LP per
// independent subproblem, or one in all when the options turn decomposition off.
SolveSize SolveSizeOf(const v1::MeshStats& stats, const QuantizeOptions& options);

// The solver's working memory for a solve of this size, held while the job is queued or runs.
int64_t SolverBytes(const SolveSize& size);

// A finished job as the store retains it, with `result` (nullptr for a job that failed).
int64_t RetainedJobBytes(const v1::QuantizationResult* result);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MEMORY_MEMORY_ESTIMATES_H_
