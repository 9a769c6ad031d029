// SPDX-License-Identifier: Apache-2.0
// The anytime start of a large ISP run (IspTuning::layered_start_min_arcs): the q of the
// parametrization's layers (core/isp/parametric_layers.h), checked for consistency and by the
// run's separation check, and reported as its first valid q (phase LAYERS) before the engine
// builds its LPs. On a 100k-arc part that is 0.09-0.13 s CPU into a run of 1.4-9.8 s; the ISP
// path that follows starts from q = 0 as always, and only replaces this q once it finds a better
// valid one.
#ifndef ISPQ_CORE_ISP_LAYERED_START_H_
#define ISPQ_CORE_ISP_LAYERED_START_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/run_clock.h"
#include "core/quantization_progress.h"
#include "core/quantize_result.h"
#include "core/separation_check.h"
#include "core/tmesh.h"

namespace ispq {

struct ValidStart {
  std::vector<int64_t> values;  // per bundle
  double objective = 0;
};

// The layered q if it is consistent and `separation` finds nothing, reported to `observer` (may
// be null); nullopt otherwise. `quantization` holds the targets s * l of `scaling`. Adds the
// tracing time to stats.layers_seconds and the search's to stats.separation_search_seconds.
std::optional<ValidStart> FindLayeredStart(const TMesh& mesh, const ConsistencyMatrix& consistency,
                                           const ArcBundles& bundles,
                                           const BundleQuantization& quantization, double scaling,
                                           SeparationCheck& separation, const RunClock& clock,
                                           QuantizeStats& stats, ProgressObserver* observer);

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_LAYERED_START_H_
