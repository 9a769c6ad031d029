// The 24 orientation-preserving rotations of the cube, as small value types with table lookups.
//
// A rotation maps vectors of one block frame to another (the rotational part of a patch
// transition). The format writes it as a signed permutation r = (r0, r1, r2) acting as
// (R x)_i = sign(r_i) * x[|r_i| - 1]. Here a rotation is an index 0..23 into precomputed
// tables, so composing, inverting and mapping directions are array lookups in hot loops (the
// separation search composes rotations on every patch crossing).
#ifndef ISPQ_CORE_ROTATION_H_
#define ISPQ_CORE_ROTATION_H_

#include <array>
#include <cstdint>
#include <optional>

#include "core/direction.h"

namespace ispq {

class Rotation {
 public:
  static constexpr int kCount = 24;

  constexpr Rotation() = default;  // identity

  // nullopt unless r is a permutation of {±1, ±2, ±3} with determinant +1.
  static std::optional<Rotation> FromSignedPermutation(const std::array<int, 3>& r);
  static Rotation FromIndex(int index) { return Rotation(static_cast<uint8_t>(index)); }

  int index() const { return index_; }
  bool IsIdentity() const { return index_ == 0; }
  std::array<int, 3> SignedPermutation() const;

  Dir Apply(Dir d) const;
  std::array<int64_t, 3> Apply(const std::array<int64_t, 3>& x) const;
  std::array<double, 3> Apply(const std::array<double, 3>& x) const;
  Rotation Inverse() const;

  // Rotation that first applies `first`, then `*this` (matrix product this * first).
  Rotation After(Rotation first) const;

  friend bool operator==(Rotation a, Rotation b) { return a.index_ == b.index_; }

 private:
  explicit constexpr Rotation(uint8_t index) : index_(index) {}
  uint8_t index_ = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ROTATION_H_
