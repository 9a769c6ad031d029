// The 24 rotations as flat lookup tables that inline into hot loops.
//
// core/rotation.h is the rotation value type used everywhere; its operations are out-of-line
// table lookups. The separation search maps directions, integer vectors and boxes by rotations
// on every patch crossing and every candidate step, so it reads these tables instead: built once
// from Rotation, indexed by Rotation::index().
#ifndef ISPQ_CORE_ROTATION_TABLES_H_
#define ISPQ_CORE_ROTATION_TABLES_H_

#include <array>
#include <cstdint>

#include "core/direction.h"
#include "core/integer_box.h"
#include "core/rotation.h"

namespace ispq {

class RotationTables {
 public:
  static const RotationTables& Get();

  uint8_t Inverse(uint8_t r) const { return inverse_[r]; }
  // Index of Rotation::FromIndex(outer).After(Rotation::FromIndex(inner)).
  uint8_t After(uint8_t outer, uint8_t inner) const { return after_[outer][inner]; }
  Dir Apply(uint8_t r, Dir d) const { return dir_image_[r][DirIndex(d)]; }
  IntVec3 Apply(uint8_t r, const IntVec3& x) const {
    IntVec3 y;
    for (int i = 0; i < 3; ++i) {
      const int64_t value = x[source_axis_[r][i]];
      y[i] = negate_[r][i] ? -value : value;
    }
    return y;
  }
  // The image of a non-inverted box, again sorted per axis.
  IntBox Apply(uint8_t r, const IntBox& box) const {
    IntBox result;
    for (int i = 0; i < 3; ++i) {
      const int source = source_axis_[r][i];
      if (negate_[r][i]) {
        result.lo[i] = -box.hi[source];
        result.hi[i] = -box.lo[source];
      } else {
        result.lo[i] = box.lo[source];
        result.hi[i] = box.hi[source];
      }
    }
    return result;
  }

 private:
  RotationTables();

  std::array<uint8_t, Rotation::kCount> inverse_{};
  std::array<std::array<uint8_t, Rotation::kCount>, Rotation::kCount> after_{};
  std::array<std::array<Dir, kNumDirs>, Rotation::kCount> dir_image_{};
  // (R x)_i = (negate_[i] ? -1 : 1) * x[source_axis_[i]].
  std::array<std::array<uint8_t, 3>, Rotation::kCount> source_axis_{};
  std::array<std::array<bool, 3>, Rotation::kCount> negate_{};
};

}  // namespace ispq

#endif  // ISPQ_CORE_ROTATION_TABLES_H_
