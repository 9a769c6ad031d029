// SPDX-License-Identifier: Apache-2.0
// Block extents and the non-negativity rows C of the paper (eq. 1d, block form): a block's extent
// along an axis is the sum of q over one of its four edges parallel to that axis. Under consistency
// all four agree; like the reference, the rows use the edge on the positive side of the two other
// axes, and the hex count uses the edge on their negative side (proto/README.md, sections
// Non-negativity and Objective and hex count).
#ifndef ISPQ_CORE_BLOCK_EXTENTS_H_
#define ISPQ_CORE_BLOCK_EXTENTS_H_

#include <cstdint>
#include <optional>
#include <span>

#include "core/tmesh.h"

namespace ispq {

// Arcs whose sum is the extent row of block b along `axis`.
std::span<const ArcId> ExtentRowArcs(const TMesh& mesh, BlockId b, int axis);

int64_t BlockExtent(const TMesh& mesh, BlockId b, int axis, std::span<const int64_t> q);

// Sum over blocks of the product of the three extents (meaningful for a valid q only); nullopt if
// it does not fit int64. q must lie in the representable range (core/quantization_limits.h), so
// that the extents themselves do.
std::optional<int64_t> HexCount(const TMesh& mesh, std::span<const int64_t> q);

// The same sum over the continuous (unscaled) lengths: the hex count at scaling 1 before
// rounding. Scaling by s multiplies it by s^3.
double ContinuousHexVolume(const TMesh& mesh);

}  // namespace ispq

#endif  // ISPQ_CORE_BLOCK_EXTENTS_H_
