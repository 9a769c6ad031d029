// SPDX-License-Identifier: Apache-2.0
#include "core/isp/layered_start.h"

#include "core/isp/parametric_layers.h"
#include "core/quantization_objective.h"

namespace ispq {

std::optional<ValidStart> FindLayeredStart(const TMesh& mesh, const ConsistencyMatrix& consistency,
                                           const ArcBundles& bundles,
                                           const BundleQuantization& quantization, double scaling,
                                           const RunClock& clock, QuantizeStats& stats,
                                           ProgressObserver* observer) {
  std::optional<std::vector<int64_t>> values;
  {
    ScopedCpuSeconds timer(&stats.layers_seconds);
    values = QuantizeByParametricLayers(mesh, bundles, quantization);
  }
  if (!values.has_value()) return std::nullopt;
  const std::vector<int64_t> q = bundles.ArcValues(*values);
  for (const int64_t x : q) {
    if (x < 1) return std::nullopt;
  }
  for (int r = 0; r < consistency.num_rows(); ++r) {
    if (consistency.RowValue(r, q) != 0) return std::nullopt;
  }
  // Every arc is at least 1, so the simple rows hold, and every separation search settles each
  // start at its branch-offs without a walk (core/README.md, section Hopeless walks): q is
  // separating without a search.
  const double objective = QuantizationObjective(mesh, q, scaling);
  if (observer != nullptr) {
    ProgressEvent event;
    event.phase = QuantizationPhase::kLayers;
    event.iteration = 0;
    event.separation_round = 0;
    event.objective = objective;
    event.violated_constraints = 0;
    event.separating = true;
    event.elapsed_seconds = clock.ElapsedSeconds();
    if (observer->WantsQuantization()) event.q = q;
    observer->OnProgress(event);
  }
  return ValidStart{std::move(*values), objective};
}

}  // namespace ispq
