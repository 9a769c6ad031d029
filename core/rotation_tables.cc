#include "core/rotation_tables.h"

namespace ispq {

const RotationTables& RotationTables::Get() {
  static const RotationTables* const kTables = new RotationTables();
  return *kTables;
}

RotationTables::RotationTables() {
  for (int r = 0; r < Rotation::kCount; ++r) {
    const Rotation rotation = Rotation::FromIndex(r);
    inverse_[r] = static_cast<uint8_t>(rotation.Inverse().index());
    for (int s = 0; s < Rotation::kCount; ++s) {
      after_[r][s] = static_cast<uint8_t>(rotation.After(Rotation::FromIndex(s)).index());
    }
    for (Dir d : kAllDirs) dir_image_[r][DirIndex(d)] = rotation.Apply(d);
    const std::array<int, 3> perm = rotation.SignedPermutation();
    for (int i = 0; i < 3; ++i) {
      source_axis_[r][i] = static_cast<uint8_t>((perm[i] > 0 ? perm[i] : -perm[i]) - 1);
      negate_[r][i] = perm[i] < 0;
    }
  }
}

}  // namespace ispq
