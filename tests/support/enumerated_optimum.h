// SPDX-License-Identifier: Apache-2.0
// The optimal quantization of a tiny T-mesh by brute force, for tests that need an answer no
// algorithm of the product computed: every consistent q whose bundles (arcs forced equal) lie
// within `radius` of the rounded mean target of the bundle and are >= 0, in order of objective,
// until the validator (core/quantization_validator.h) accepts one. Far from the targets q only
// gets worse, so on the meshes the tests use that is the global optimum over valid q.
#ifndef ISPQ_TESTS_SUPPORT_ENUMERATED_OPTIMUM_H_
#define ISPQ_TESTS_SUPPORT_ENUMERATED_OPTIMUM_H_

#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "core/tmesh.h"

namespace ispq::testing {

struct EnumeratedOptimum {
  double objective;
  std::vector<int64_t> q;  // per arc
};

// d(q) = sum_a (q_a - s l_a)^2.
double QuantizationObjective(const TMesh& mesh, double scaling, const std::vector<int64_t>& q);

// RESOURCE_EXHAUSTED if there are more than 5 million candidates; NOT_FOUND if none is valid.
absl::StatusOr<EnumeratedOptimum> EnumerateOptimum(const TMesh& mesh, double scaling, int radius);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_ENUMERATED_OPTIMUM_H_
