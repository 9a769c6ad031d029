// SPDX-License-Identifier: Apache-2.0
// OPTIMALINTEGERSTEP of the paper (Alg. 1): the best multiplicity t of an integer sheet
// (core/README.md, section From a rational vertex to an integer step).
//
// Applying t times a sheet changes the objective by f(t) = a t^2 + b t with a > 0, a convex
// parabola, so the best integer in a feasible interval is the rounded vertex clamped to the
// interval. Taking more than one copy of a sheet at once is only a shortcut: the same state
// would be reached by popping the same root repeatedly, at one LP solve per copy.
#ifndef ISPQ_CORE_ISP_INTEGER_STEP_H_
#define ISPQ_CORE_ISP_INTEGER_STEP_H_

#include <cstdint>

namespace ispq {

// The integer t in [t_min, t_max] minimizing a t^2 + b t (a > 0, t_min <= t_max).
int64_t OptimalIntegerStep(double a, double b, int64_t t_min, int64_t t_max);

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_INTEGER_STEP_H_
