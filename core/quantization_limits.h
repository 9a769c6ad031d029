// SPDX-License-Identifier: Apache-2.0
// The numeric range every quantization stays in, and the check that a request's targets fit it.
//
// q travels as int32 in the API (proto/ispq/v1/quantization.proto) and is computed in int64.
// Requests whose targets s * l_a would leave the range are refused before any work, with
// INVALID_ARGUMENT naming the limit; the validator refuses any q outside it and any hex count
// that does not fit int64, so that a wrapped or overflowed value is never certified. Inside the
// range, patch side sums and block extents (at most 2^30 arcs of at most 2^30 each) fit int64.
#ifndef ISPQ_CORE_QUANTIZATION_LIMITS_H_
#define ISPQ_CORE_QUANTIZATION_LIMITS_H_

#include <cstdint>

#include "absl/status/status.h"
#include "core/tmesh.h"

namespace ispq {

// The largest |q_a| of a valid quantization.
inline constexpr int64_t kMaxArcLength = int64_t{1} << 30;

// The largest target s * l_a a request may ask for: a quarter of kMaxArcLength, so that the
// sheets around a target never come near the edge of the range.
inline constexpr double kMaxTargetLength = static_cast<double>(int64_t{1} << 28);

// The largest hex count of the scaled continuous targets, s^3 * ContinuousHexVolume: far beyond
// any mesh that can be built, far below int64's range.
inline constexpr double kMaxTargetHexes = 1e15;

// INVALID_ARGUMENT if scaling the mesh's lengths by `scaling` gives an arc a target above
// kMaxTargetLength or the blocks more than kMaxTargetHexes hexes; the message names the arc or
// the count and the limit. `scaling` must be finite and > 0.
absl::Status CheckTargetsRepresentable(const TMesh& mesh, double scaling);

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZATION_LIMITS_H_
