// SPDX-License-Identifier: Apache-2.0
#include "tests/fuzz/bounded_quantize.h"

#include <algorithm>
#include <cstdio>

#include "core/quantization_validator.h"

namespace ispq::fuzz {

void QuantizeBounded(const TMesh& mesh, QuantizeOptions options) {
  if (mesh.num_arcs() > kMaxArcsToQuantize) return;
  options.time_limit_seconds = std::min(options.time_limit_seconds, 0.2);
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  if (!result.ok()) {
    // Refusals of options are expected; the solver itself must not fail.
    if (result.status().code() != absl::StatusCode::kInvalidArgument) {
      std::fprintf(stderr, "Quantize failed: %s\n", result.status().ToString().c_str());
      __builtin_trap();
    }
    return;
  }
  if (!result->valid) return;
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, result->q);
  if (!report.ok() || !report->valid()) {
    std::fprintf(stderr, "a result called valid is not: %s\n",
                 report.ok() ? report->Describe().c_str() : report.status().ToString().c_str());
    __builtin_trap();
  }
}

}  // namespace ispq::fuzz
