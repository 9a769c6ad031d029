#include "core/rotation.h"

#include <cstdlib>

namespace ispq {
namespace {

using SignedPerm = std::array<int, 3>;

int Determinant(const SignedPerm& r) {
  // Sign of the permutation times the product of the signs.
  int perm[3];
  int sign = 1;
  for (int i = 0; i < 3; ++i) {
    perm[i] = std::abs(r[i]) - 1;
    if (r[i] < 0) sign = -sign;
  }
  int inversions = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) inversions += perm[i] > perm[j] ? 1 : 0;
  }
  return inversions % 2 == 0 ? sign : -sign;
}

bool IsSignedPermutation(const SignedPerm& r) {
  bool seen[3] = {false, false, false};
  for (int v : r) {
    const int a = std::abs(v);
    if (a < 1 || a > 3 || seen[a - 1]) return false;
    seen[a - 1] = true;
  }
  return true;
}

// All tables are derived once from the list of 24 signed permutations, identity first.
struct Tables {
  std::array<SignedPerm, Rotation::kCount> perm{};
  std::array<std::array<uint8_t, kNumDirs>, Rotation::kCount> dir_image{};
  std::array<uint8_t, Rotation::kCount> inverse{};
  std::array<std::array<uint8_t, Rotation::kCount>, Rotation::kCount> after{};  // [outer][inner]

  Tables() {
    int n = 0;
    perm[n++] = {1, 2, 3};
    const int axes[6][3] = {{1, 2, 3}, {1, 3, 2}, {2, 1, 3}, {2, 3, 1}, {3, 1, 2}, {3, 2, 1}};
    for (const auto& p : axes) {
      for (int signs = 0; signs < 8; ++signs) {
        SignedPerm r = {p[0] * ((signs & 1) ? -1 : 1), p[1] * ((signs & 2) ? -1 : 1),
                        p[2] * ((signs & 4) ? -1 : 1)};
        if (Determinant(r) != 1 || r == SignedPerm{1, 2, 3}) continue;
        perm[n++] = r;
      }
    }
    for (int i = 0; i < Rotation::kCount; ++i) {
      for (Dir d : kAllDirs) dir_image[i][DirIndex(d)] = static_cast<uint8_t>(MapDir(perm[i], d));
    }
    for (int i = 0; i < Rotation::kCount; ++i) {
      for (int j = 0; j < Rotation::kCount; ++j) {
        // (R_i R_j) as signed permutation: c_k = sign(ri_k) * rj[|ri_k| - 1].
        SignedPerm c;
        for (int k = 0; k < 3; ++k) {
          const int rik = perm[i][k];
          c[k] = (rik > 0 ? 1 : -1) * perm[j][std::abs(rik) - 1];
        }
        after[i][j] = static_cast<uint8_t>(IndexOf(c));
        if (c == SignedPerm{1, 2, 3}) inverse[i] = static_cast<uint8_t>(j);
      }
    }
  }

  // Image of direction d: e_{axis(d)} * sign goes to component i where |r_i| - 1 == axis(d).
  static Dir MapDir(const SignedPerm& r, Dir d) {
    for (int i = 0; i < 3; ++i) {
      if (std::abs(r[i]) - 1 == AxisOf(d)) {
        const bool negative = IsNegative(d) != (r[i] < 0);
        return MakeDir(i, negative);
      }
    }
    return d;  // unreachable for a valid permutation
  }

  int IndexOf(const SignedPerm& r) const {
    for (int i = 0; i < Rotation::kCount; ++i) {
      if (perm[i] == r) return i;
    }
    return -1;
  }
};

const Tables& GetTables() {
  static const Tables* const kTables = new Tables();
  return *kTables;
}

}  // namespace

std::optional<Rotation> Rotation::FromSignedPermutation(const std::array<int, 3>& r) {
  if (!IsSignedPermutation(r) || Determinant(r) != 1) return std::nullopt;
  return Rotation(static_cast<uint8_t>(GetTables().IndexOf(r)));
}

std::array<int, 3> Rotation::SignedPermutation() const { return GetTables().perm[index_]; }

Dir Rotation::Apply(Dir d) const {
  return static_cast<Dir>(GetTables().dir_image[index_][DirIndex(d)]);
}

std::array<int64_t, 3> Rotation::Apply(const std::array<int64_t, 3>& x) const {
  const SignedPerm& r = GetTables().perm[index_];
  std::array<int64_t, 3> y;
  for (int i = 0; i < 3; ++i) y[i] = (r[i] > 0 ? 1 : -1) * x[std::abs(r[i]) - 1];
  return y;
}

std::array<double, 3> Rotation::Apply(const std::array<double, 3>& x) const {
  const SignedPerm& r = GetTables().perm[index_];
  std::array<double, 3> y;
  for (int i = 0; i < 3; ++i) y[i] = (r[i] > 0 ? 1.0 : -1.0) * x[std::abs(r[i]) - 1];
  return y;
}

Rotation Rotation::Inverse() const { return Rotation(GetTables().inverse[index_]); }

Rotation Rotation::After(Rotation first) const {
  return Rotation(GetTables().after[index_][first.index_]);
}

}  // namespace ispq
