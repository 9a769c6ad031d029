// SPDX-License-Identifier: Apache-2.0
// The objective the quantization minimises (eq. 1 of the paper; proto/README.md, section Objective
// and hex count): d(q, s*l), the sum over arcs of (q_a - s * l_a)^2. One definition, used wherever
// a q is scored against its targets: the quantizer's result and the CLI's `validate`, so that both
// print the same number for one q.
#ifndef ISPQ_CORE_QUANTIZATION_OBJECTIVE_H_
#define ISPQ_CORE_QUANTIZATION_OBJECTIVE_H_

#include <cstdint>
#include <span>

#include "core/tmesh.h"

namespace ispq {

// `q` has one entry per arc of `mesh`; `scaling` is the s of the targets s * l.
double QuantizationObjective(const TMesh& mesh, std::span<const int64_t> q, double scaling);

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZATION_OBJECTIVE_H_
