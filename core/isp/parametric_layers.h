// SPDX-License-Identifier: Apache-2.0
// A consistent integer quantization with every arc at least 1, built without an LP: the first
// valid q of a large run (the anytime start of core/isp/integer_sheet_pump.h).
//
// The T-mesh comes with the continuous parametrization it was cut from (every node's coordinates
// in each block frame, proto/README.md, section Block frames). An iso-surface of one coordinate,
// followed from block to block through the patches, crosses every patch it enters at one arc on
// each of the two opposite sides; counting the crossings per arc gives an integer sheet: every
// consistency row gains as much on one side as on the other. Adding layers until every arc is
// crossed gives a q >= 1 everywhere: no block degenerates, so the simple rows and the block
// extents hold by construction, and no critical entities are expected to collapse. The caller
// (core/isp/layered_start.h) still checks consistency and runs the separation search before it
// calls the q valid (the search found nothing on every mesh tried). Each layer is then weighted by
// the integer multiplicity (at least 1) that brings its arcs closest to their targets.
//
// Cost: O(crossings * patch perimeter) with no LP, 4-6 ms per 10k arcs; the work is bounded by a
// multiple of the mesh's size whatever the input. A layer that does not close (a seam whose
// translation makes the iso-surface spiral, as on one of the 62 shared meshes) exhausts its
// budget; then there is no such q and the caller does without.
#ifndef ISPQ_CORE_ISP_PARAMETRIC_LAYERS_H_
#define ISPQ_CORE_ISP_PARAMETRIC_LAYERS_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "core/arc_bundles.h"
#include "core/isp/bundle_quantization.h"
#include "core/tmesh.h"

namespace ispq {

// Values per bundle (each >= 1, consistent) that minimize the objective of `quantization` over
// the multiplicities of the traced layers; nullopt if some layer did not close.
std::optional<std::vector<int64_t>> QuantizeByParametricLayers(
    const TMesh& mesh, const ArcBundles& bundles, const BundleQuantization& quantization);

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_PARAMETRIC_LAYERS_H_
