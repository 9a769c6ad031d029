// SPDX-License-Identifier: Apache-2.0
// How far each bundle may stray from its best integer in the exact model
// (core/exact/bundle_objective.h), given a known q.
//
// The rows split the bundles into independent components; the optimum restricted to one of them
// is optimal for it alone. Where the known q satisfies a component's rows, the optimum therefore
// spends no more on that component than q does, and the component's slack is q's objective on it
// minus the component's minimum. Elsewhere only the global bound holds: q's total objective minus
// the total minimum. Per-component slacks keep the windows, and with them the model, linear in
// the size of the mesh instead of growing with the total slack of all components.
#ifndef ISPQ_CORE_EXACT_WINDOW_SLACKS_H_
#define ISPQ_CORE_EXACT_WINDOW_SLACKS_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/exact/bundle_objective.h"
#include "core/exact/quantization_constraints.h"

namespace ispq {

// Per bundle, the slack of its window for solutions at least as good as the known q (per-bundle
// values x); every optimal q lies within the windows.
std::vector<double> WindowSlacks(const BundleObjectives& objectives,
                                 const QuantizationConstraints& constraints,
                                 std::span<const int64_t> x);

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_WINDOW_SLACKS_H_
