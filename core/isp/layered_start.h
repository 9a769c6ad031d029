// SPDX-License-Identifier: Apache-2.0
// The anytime start of a large ISP run (IspTuning::layered_start_min_arcs): the q of the
// parametrization's layers (core/isp/parametric_layers.h), checked for consistency, and reported
// as its first valid q (phase LAYERS) before the engine builds its LPs or its separation search.
// Every arc of it is at least 1, and such a q passes every separation search: each start is
// settled at its branch-offs (core/README.md, section Hopeless walks), so it is not searched. The
// descent then goes on from it (IspTuning::descend_from_layered_start), and the run only replaces
// it once it finds a better valid q.
#ifndef ISPQ_CORE_ISP_LAYERED_START_H_
#define ISPQ_CORE_ISP_LAYERED_START_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/quantization_progress.h"
#include "core/quantize_result.h"
#include "core/run_clock.h"
#include "core/tmesh.h"

namespace ispq {

struct ValidStart {
  std::vector<int64_t> values;  // per bundle
  double objective = 0;
};

// The layered q if it is consistent with every arc >= 1, reported to `observer` (may be null);
// nullopt otherwise. `quantization` holds the targets s * l of `scaling`. Adds the tracing time
// to stats.layers_seconds.
std::optional<ValidStart> FindLayeredStart(const TMesh& mesh, const ConsistencyMatrix& consistency,
                                           const ArcBundles& bundles,
                                           const BundleQuantization& quantization, double scaling,
                                           const RunClock& clock, QuantizeStats& stats,
                                           ProgressObserver* observer);

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_LAYERED_START_H_
