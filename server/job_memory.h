// SPDX-License-Identifier: Apache-2.0
// The memory budget's estimates (server/memory_budget.h) of what meshes, jobs and results hold.
//
// Measured on the shared T-meshes and disjoint copies of them (glibc heap and peak RSS):
//   * a validated core TMesh takes 1.2-1.7 times the size of its binary protobuf;
//   * the solver's working memory while a job runs is 2.7-13 KB per arc, most of it one CLP
//     model per independent subproblem (8000 copies of a cube: 96k arcs, 1.16 GB; 200 copies of
//     the femur shell: 59k arcs, 280 MB);
//   * a retained result is its q (4 bytes per arc) and a few small messages.
// The estimates take the upper end, so that a budget that admits a job can also run it.
#ifndef ISPQ_SERVER_JOB_MEMORY_H_
#define ISPQ_SERVER_JOB_MEMORY_H_

#include <cstdint>

#include "ispq/v1/quantization.pb.h"

namespace ispq::server {

inline constexpr int64_t kSolverBytesPerArc = 16 << 10;
// A job's own objects (its events, names, options) besides mesh and result.
inline constexpr int64_t kJobOverheadBytes = 8 << 10;

// The core TMesh validated from a mesh of `wire_bytes` binary protobuf bytes.
inline int64_t MeshBytes(int64_t wire_bytes) { return 2 * wire_bytes + kJobOverheadBytes; }

// The solver's working memory for a mesh of `arcs` arcs, held while the job is queued or runs.
inline int64_t SolverBytes(int64_t arcs) { return kSolverBytesPerArc * arcs + kJobOverheadBytes; }

// A finished job as the store retains it, with `result` (nullptr for a job that failed).
int64_t RetainedJobBytes(const v1::QuantizationResult* result);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOB_MEMORY_H_
