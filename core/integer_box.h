// SPDX-License-Identifier: Apache-2.0
// Integer points and axis-aligned boxes in a block or search frame, with the closed-overlap test
// the separation search is built on (core/README.md, sections Integer positions, The fan, Block
// admissibility and the two block-box modes, and Violation tests).
//
// Positions are sums of integer arc lengths, so everything is exact int64 arithmetic. A box whose
// upper bound lies below its lower bound on some axis is "inverted"; like the reference, an
// inverted box touches nothing. This is how a collapsed (negative-length) start entity or, in the
// reference-compatible mode, a block seen through a sign-flipping rotation is rejected.
#ifndef ISPQ_CORE_INTEGER_BOX_H_
#define ISPQ_CORE_INTEGER_BOX_H_

#include <algorithm>
#include <array>
#include <cstdint>

#include "core/direction.h"
#include "core/rotation.h"

namespace ispq {

using IntVec3 = std::array<int64_t, 3>;

struct IntBox {
  IntVec3 lo;
  IntVec3 hi;
};

inline IntVec3 Add(const IntVec3& a, const IntVec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline IntVec3 Subtract(const IntVec3& a, const IntVec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
// a + length * (unit vector of d).
inline IntVec3 AddAlong(const IntVec3& a, Dir d, int64_t length) {
  IntVec3 result = a;
  result[AxisOf(d)] += IsNegative(d) ? -length : length;
  return result;
}

inline IntBox PointBox(const IntVec3& p) { return {p, p}; }

// The box spanned by two corners, sorted per axis.
inline IntBox SpannedBox(const IntVec3& a, const IntVec3& b) {
  IntBox box;
  for (int i = 0; i < 3; ++i) {
    box.lo[i] = std::min(a[i], b[i]);
    box.hi[i] = std::max(a[i], b[i]);
  }
  return box;
}

inline bool IsInverted(const IntBox& box) {
  return box.hi[0] < box.lo[0] || box.hi[1] < box.lo[1] || box.hi[2] < box.lo[2];
}

// Closed-interval overlap on all three axes of two boxes that are not inverted.
inline bool Overlap(const IntBox& a, const IntBox& b) {
  for (int i = 0; i < 3; ++i) {
    if (a.hi[i] < b.lo[i] || b.hi[i] < a.lo[i]) return false;
  }
  return true;
}

// Closed-interval overlap; false if either box is inverted.
inline bool Touches(const IntBox& a, const IntBox& b) {
  return !IsInverted(a) && !IsInverted(b) && Overlap(a, b);
}

// The image of a non-inverted box under a rotation, again sorted per axis.
inline IntBox RotateBox(Rotation r, const IntBox& box) {
  IntBox result;
  for (int i = 0; i < 3; ++i) {
    const int source = r.SourceAxis(i);
    if (r.NegatesAxis(i)) {
      result.lo[i] = -box.hi[source];
      result.hi[i] = -box.lo[source];
    } else {
      result.lo[i] = box.lo[source];
      result.hi[i] = box.hi[source];
    }
  }
  return result;
}

}  // namespace ispq

#endif  // ISPQ_CORE_INTEGER_BOX_H_
