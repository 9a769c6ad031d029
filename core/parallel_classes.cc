// SPDX-License-Identifier: Apache-2.0
#include "core/parallel_classes.h"

#include "core/direction.h"
#include "core/disjoint_sets.h"
#include "core/invariant.h"

namespace ispq {

ParallelClasses::ParallelClasses(const TMesh& mesh) {
  DisjointSets sets(3 * mesh.num_blocks());
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    const BlockId from = mesh.patch_block(p, 0);
    const BlockId to = mesh.patch_block(p, 1);
    if (from == kNoId || to == kNoId) continue;  // a boundary patch joins nothing
    const Rotation rotation = mesh.patch_rotation(p);
    for (int axis = 0; axis < 3; ++axis) {
      sets.Join(3 * from + axis, 3 * to + AxisOf(rotation.Apply(MakeDir(axis, false))));
    }
  }
  // The smallest member represents each set, so numbering the representatives in id order
  // numbers the classes by their smallest pair.
  of_block_axis_.resize(3 * static_cast<size_t>(mesh.num_blocks()));
  for (int32_t i = 0; i < static_cast<int32_t>(of_block_axis_.size()); ++i) {
    const int32_t root = sets.Find(i);
    of_block_axis_[i] = root == i ? num_classes_++ : of_block_axis_[root];
  }
  of_arc_.resize(mesh.num_arcs());
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const BlockId b = mesh.arc_blocks(a).front();
    const std::optional<Dir> dir = mesh.HalfarcDirInBlock(HalfarcOf(a, false), b);
    ISPQ_INVARIANT(dir.has_value(), "an arc lies on the boundary of every block around it");
    of_arc_[a] = of_block_axis(b, AxisOf(*dir));
  }
}

}  // namespace ispq
