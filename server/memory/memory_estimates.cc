// SPDX-License-Identifier: Apache-2.0
#include "server/memory/memory_estimates.h"

#include <algorithm>

namespace ispq::server {

SolveSize SolveSizeOf(const v1::MeshStats& stats, const QuantizeOptions& options) {
  return SolveSize{
      .arcs = stats.arcs(),
      .bundles = stats.bundles(),
      .subproblems = options.decompose ? stats.subproblems() : std::min(stats.subproblems(), 1),
      .exact = options.method == QuantizationMethod::kExact,
  };
}

int64_t SolverBytes(const SolveSize& size) {
  // Each LP at kLpBaseBytes plus kLpBytesPerBundle per bundle, at most kLpMaxBytes.
  const int64_t lps = std::min(kLpMaxBytes * size.subproblems,
                               kLpBaseBytes * size.subproblems + kLpBytesPerBundle * size.bundles);
  const int64_t exact = size.exact ? kExactBaseBytes + kExactBytesPerArc * size.arcs : 0;
  return kJobOverheadBytes + kSolverBaseBytes + kSolverBytesPerArc * size.arcs +
         kSolverBytesPerBundle * size.bundles + lps + exact;
}

int64_t RetainedJobBytes(const v1::QuantizationResult* result) {
  // The terminal event keeps the result; ToProto copies are transient and budgeted as responses.
  return kJobOverheadBytes +
         (result != nullptr ? static_cast<int64_t>(result->SpaceUsedLong()) : 0);
}

}  // namespace ispq::server
