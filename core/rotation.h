// SPDX-License-Identifier: Apache-2.0
// The 24 orientation-preserving rotations of the cube, as one-byte values with table lookups.
//
// A rotation maps vectors of one block frame to another (the rotational part of a patch
// transition). The format writes it as a signed permutation r = (r0, r1, r2) acting as
// (R x)_i = sign(r_i) * x[|r_i| - 1]. Here a rotation is an index 0..23 into tables computed at
// compile time, so composing, inverting and mapping directions or integer vectors are inline
// array lookups: the separation search does this on every patch crossing and candidate step.
#ifndef ISPQ_CORE_ROTATION_H_
#define ISPQ_CORE_ROTATION_H_

#include <array>
#include <cstdint>
#include <optional>

#include "core/direction.h"

namespace ispq {

namespace rotation_internal {

using SignedPerm = std::array<int, 3>;
inline constexpr int kCount = 24;

constexpr int Abs(int x) { return x < 0 ? -x : x; }

constexpr bool IsSignedPermutation(const SignedPerm& r) {
  bool seen[3] = {false, false, false};
  for (int v : r) {
    const int a = Abs(v);
    if (a < 1 || a > 3 || seen[a - 1]) return false;
    seen[a - 1] = true;
  }
  return true;
}

// Sign of the permutation times the product of the signs.
constexpr int Determinant(const SignedPerm& r) {
  int sign = 1, inversions = 0;
  for (int i = 0; i < 3; ++i) {
    if (r[i] < 0) sign = -sign;
    for (int j = i + 1; j < 3; ++j) inversions += Abs(r[i]) > Abs(r[j]) ? 1 : 0;
  }
  return inversions % 2 == 0 ? sign : -sign;
}

struct Tables {
  std::array<SignedPerm, kCount> perm{};
  // (R x)_i = (negate[i] ? -1 : 1) * x[source_axis[i]].
  std::array<std::array<uint8_t, 3>, kCount> source_axis{};
  std::array<std::array<bool, 3>, kCount> negate{};
  std::array<std::array<Dir, kNumDirs>, kCount> dir_image{};
  std::array<uint8_t, kCount> inverse{};
  std::array<std::array<uint8_t, kCount>, kCount> after{};  // [outer][inner]

  constexpr int IndexOf(const SignedPerm& r) const {
    for (int i = 0; i < kCount; ++i) {
      if (perm[i] == r) return i;
    }
    return -1;
  }
};

// Identity first, then the other proper signed permutations in a fixed order.
constexpr Tables BuildTables() {
  Tables t;
  int n = 0;
  t.perm[n++] = {1, 2, 3};
  constexpr int kAxes[6][3] = {{1, 2, 3}, {1, 3, 2}, {2, 1, 3}, {2, 3, 1}, {3, 1, 2}, {3, 2, 1}};
  for (const auto& p : kAxes) {
    for (int signs = 0; signs < 8; ++signs) {
      const SignedPerm r = {p[0] * ((signs & 1) ? -1 : 1), p[1] * ((signs & 2) ? -1 : 1),
                            p[2] * ((signs & 4) ? -1 : 1)};
      if (Determinant(r) != 1 || r == SignedPerm{1, 2, 3}) continue;
      t.perm[n++] = r;
    }
  }
  for (int i = 0; i < kCount; ++i) {
    for (int k = 0; k < 3; ++k) {
      t.source_axis[i][k] = static_cast<uint8_t>(Abs(t.perm[i][k]) - 1);
      t.negate[i][k] = t.perm[i][k] < 0;
      // e_{source} * sign maps to component k.
      for (int neg = 0; neg < 2; ++neg) {
        const Dir from = MakeDir(t.source_axis[i][k], neg != 0);
        t.dir_image[i][DirIndex(from)] = MakeDir(k, (neg != 0) != t.negate[i][k]);
      }
    }
  }
  for (int i = 0; i < kCount; ++i) {
    for (int j = 0; j < kCount; ++j) {
      // (R_i R_j) as signed permutation: c_k = sign(ri_k) * rj[|ri_k| - 1].
      SignedPerm c{};
      for (int k = 0; k < 3; ++k) {
        const int rik = t.perm[i][k];
        c[k] = (rik > 0 ? 1 : -1) * t.perm[j][Abs(rik) - 1];
      }
      t.after[i][j] = static_cast<uint8_t>(t.IndexOf(c));
      if (c == SignedPerm{1, 2, 3}) t.inverse[i] = static_cast<uint8_t>(j);
    }
  }
  return t;
}

inline constexpr Tables kTables = BuildTables();

}  // namespace rotation_internal

class Rotation {
 public:
  static constexpr int kCount = rotation_internal::kCount;

  constexpr Rotation() = default;  // identity

  // nullopt unless r is a permutation of {±1, ±2, ±3} with determinant +1.
  static constexpr std::optional<Rotation> FromSignedPermutation(const std::array<int, 3>& r) {
    if (!rotation_internal::IsSignedPermutation(r) || rotation_internal::Determinant(r) != 1) {
      return std::nullopt;
    }
    return Rotation(static_cast<uint8_t>(rotation_internal::kTables.IndexOf(r)));
  }
  static constexpr Rotation FromIndex(int index) { return Rotation(static_cast<uint8_t>(index)); }

  constexpr int index() const { return index_; }
  constexpr bool IsIdentity() const { return index_ == 0; }
  constexpr std::array<int, 3> SignedPermutation() const {
    return rotation_internal::kTables.perm[index_];
  }

  constexpr Dir Apply(Dir d) const {
    return rotation_internal::kTables.dir_image[index_][DirIndex(d)];
  }
  template <typename T>
  constexpr std::array<T, 3> Apply(const std::array<T, 3>& x) const {
    const auto& t = rotation_internal::kTables;
    std::array<T, 3> y{};
    for (int i = 0; i < 3; ++i) {
      const T value = x[t.source_axis[index_][i]];
      y[i] = t.negate[index_][i] ? -value : value;
    }
    return y;
  }
  // Where component i of the image comes from: (R x)_i = ±x[SourceAxis(i)].
  constexpr int SourceAxis(int i) const {
    return rotation_internal::kTables.source_axis[index_][i];
  }
  constexpr bool NegatesAxis(int i) const { return rotation_internal::kTables.negate[index_][i]; }

  constexpr Rotation Inverse() const {
    return Rotation(rotation_internal::kTables.inverse[index_]);
  }
  // Rotation that first applies `first`, then `*this` (matrix product this * first).
  constexpr Rotation After(Rotation first) const {
    return Rotation(rotation_internal::kTables.after[index_][first.index_]);
  }

  friend constexpr bool operator==(Rotation a, Rotation b) { return a.index_ == b.index_; }

 private:
  explicit constexpr Rotation(uint8_t index) : index_(index) {}
  uint8_t index_ = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ROTATION_H_
