// SPDX-License-Identifier: Apache-2.0
// Integer-Sheet-Pump quantization (Brueckler & Campen 2024; core/README.md, section Pipeline):
// integer arc lengths q that are consistent, give no block a negative extent and are separating,
// minimizing d(q) = sum_a (q_a - s * l_a)^2 by a greedy sequence of small sheet LPs
// (core/isp/). In exact mode the ISP result then warm-starts a MILP with the lazy separation loop
// until optimality is proven or the time limit passes (core/exact/). Every valid result carries
// a lower bound and its gap when asked (by default for meshes up to kAutoLowerBoundMaxArcs arcs;
// always in exact mode), certified for the separation rows the run found
// (core/exact/lower_bound.h); every result goes through the validator before it is returned.
//
// This is the entry point used in-process by the CLI and by every server worker. One call runs
// on the calling thread only.
#ifndef ISPQ_CORE_QUANTIZER_H_
#define ISPQ_CORE_QUANTIZER_H_

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/quantization_progress.h"
#include "core/quantize_options.h"
#include "core/quantize_result.h"
#include "core/solve_interrupter.h"
#include "core/tmesh.h"

namespace ispq {

// INVALID_ARGUMENT naming the option or the limit if `options` cannot be used on `mesh`: a
// scaling that is not finite and > 0 or whose targets leave the representable range
// (core/quantization_limits.h), a negative or NaN time limit. Quantize checks this first;
// front ends call it to refuse a request before queuing it.
absl::Status ValidateQuantizeOptions(const TMesh& mesh, const QuantizeOptions& options);

// INVALID_ARGUMENT for bad options; INTERNAL if the LP or MILP solver fails unexpectedly.
// `observer` and `interrupter` may be null.
absl::StatusOr<QuantizeResult> Quantize(const TMesh& mesh, const QuantizeOptions& options,
                                        ProgressObserver* observer = nullptr,
                                        const SolveInterrupter* interrupter = nullptr);

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZER_H_
