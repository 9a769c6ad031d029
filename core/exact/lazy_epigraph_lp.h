// SPDX-License-Identifier: Apache-2.0
// The LP relaxation of the exact model (core/exact/quantization_milp.h) solved with its secant
// rows added only where the solution needs them, on the sparse dual simplex of the sheet LPs
// (core/isp/sparse_dual_simplex.h): the lower bound of every ISP result (core/exact/lower_bound.h).
//
// The full relaxation has a secant row for every integer step of every bundle's window, and those
// are most of its rows: on the shared meshes at level 100 up to 1077 of 1171 rows, so that a dual
// simplex pivoted over a basis ten times the size of the problem (293 pivots, 18-20 M
// instructions on CLP or the sparse simplex alike, as much as the whole ISP run on some meshes).
// Here each z_b starts with the two secants around the known q's value of its bundle, and after
// each solve the secants the solution violates join, the simplex going on from its last basis.
//
// Why the value is the full relaxation's optimum: every LP on the way has a subset of the full
// model's rows, so its optimum is at most the full one's (a valid lower bound at every step); the
// last solution violates no secant within the windows, so it is feasible for the full model, and
// optimal there too.
#ifndef ISPQ_CORE_EXACT_LAZY_EPIGRAPH_LP_H_
#define ISPQ_CORE_EXACT_LAZY_EPIGRAPH_LP_H_

#include <cstdint>
#include <optional>
#include <span>

#include "core/exact/bundle_objective.h"
#include "core/exact/quantization_constraints.h"

namespace ispq {

// The optimum of the relaxation over `windows` (one per bundle, each holding x_b), starting from
// the secants around x; nullopt if the simplex could not finish (the caller then solves the full
// model on a general solver) or the rows admit nothing (only numerically possible when x
// satisfies them).
std::optional<double> SolveLazyEpigraphRelaxation(const BundleObjectives& objectives,
                                                  const QuantizationConstraints& constraints,
                                                  std::span<const IntegerWindow> windows,
                                                  std::span<const int64_t> x);

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_LAZY_EPIGRAPH_LP_H_
