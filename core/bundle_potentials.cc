// SPDX-License-Identifier: Apache-2.0
#include "core/bundle_potentials.h"

#include <algorithm>
#include <utility>

#include "core/direction.h"
#include "core/disjoint_sets.h"
#include "core/linear_terms.h"

namespace ispq {
namespace {

int DirCopy(BlockId b, Dir d) { return 6 * b + DirIndex(d); }

// b1 = b0 + b2 - chi for a solid in space, where b2 (its cavities) is its boundary shells minus
// its components b0: so b1 = shells - chi, with chi = nodes - arcs + patches - blocks.
int64_t FirstBettiNumber(const TMesh& mesh) {
  const int64_t chi =
      int64_t{mesh.num_nodes()} - mesh.num_arcs() + mesh.num_patches() - mesh.num_blocks();
  const auto on_boundary = [&mesh](PatchId p) {
    return mesh.patch_block(p, 0) == kNoId || mesh.patch_block(p, 1) == kNoId;
  };
  DisjointSets shells(mesh.num_patches());
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    PatchId last = kNoId;
    for (const HalfpatchId hp : mesh.arc_halfpatches(a)) {
      const PatchId p = hp >> 1;
      if (!on_boundary(p)) continue;
      if (last != kNoId) shells.Join(last, p);
      last = p;
    }
  }
  int64_t num_shells = 0;
  for (PatchId p = 0; p < mesh.num_patches(); ++p)
    num_shells += on_boundary(p) && shells.Find(p) == p;
  return num_shells - chi;
}

}  // namespace

std::optional<DisjointSets> GlobalBlockDirections(const TMesh& mesh) {
  DisjointSets dirs(6 * mesh.num_blocks());
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    const BlockId from = mesh.patch_block(p, 0), to = mesh.patch_block(p, 1);
    if (from == kNoId || to == kNoId) continue;
    for (const Dir d : kAllDirs) {
      dirs.Join(DirCopy(from, d), DirCopy(to, mesh.patch_rotation(p).Apply(d)));
    }
  }
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (const Dir d : kAllDirs) {
      for (const Dir e : kAllDirs) {
        if (d != e && dirs.Find(DirCopy(b, d)) == dirs.Find(DirCopy(b, e))) return std::nullopt;
      }
    }
  }
  return dirs;
}

std::optional<BundlePotentials> BundlePotentials::Compute(const TMesh& mesh,
                                                          const ConsistencyMatrix& consistency,
                                                          const ArcBundles& bundles) {
  std::optional<DisjointSets> dirs = GlobalBlockDirections(mesh);
  if (!dirs.has_value()) return std::nullopt;
  // Per arc: its global axis as a slot 0..2 (the axis in the first block of its part) and whether
  // it runs along that axis's negative direction.
  std::vector<int8_t> slot_of_set(6 * mesh.num_blocks(), -1);
  const auto axis_set = [&](BlockId b, int axis, bool* negative) {
    const int32_t plus = dirs->Find(DirCopy(b, MakeDir(axis, false)));
    const int32_t minus = dirs->Find(DirCopy(b, MakeDir(axis, true)));
    if (negative != nullptr) *negative = plus > minus;
    return std::min(plus, minus);
  };
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int axis = 0; axis < 3; ++axis) {
      int8_t& slot = slot_of_set[axis_set(b, axis, nullptr)];
      if (slot < 0) slot = static_cast<int8_t>(axis);
    }
  }
  std::vector<int8_t> slot(mesh.num_arcs());
  std::vector<uint8_t> negative(mesh.num_arcs());
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const BlockId b = mesh.arc_blocks(a).front();
    const Dir d = *mesh.HalfarcDirInBlock(HalfarcOf(a, false), b);
    bool flipped = false;
    slot[a] = slot_of_set[axis_set(b, AxisOf(d), &flipped)];
    negative[a] = IsNegative(d) != flipped;
  }
  // Per node and axis slot: the nodes an arc of another axis joins share that coordinate.
  DisjointSets coordinates(3 * mesh.num_nodes());
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    for (int s = 0; s < 3; ++s) {
      if (s != slot[a]) coordinates.Join(3 * mesh.arc_from(a) + s, 3 * mesh.arc_to(a) + s);
    }
  }
  BundlePotentials potentials;
  std::vector<int32_t> id_of_coordinate(3 * mesh.num_nodes(), kNoId);
  const auto potential = [&](NodeId n, int s) {
    int32_t& id = id_of_coordinate[coordinates.Find(3 * n + s)];
    if (id == kNoId) id = potentials.num_potentials_++;
    return id;
  };
  std::vector<int32_t> arc_tail(mesh.num_arcs()), arc_head(mesh.num_arcs());
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    arc_tail[a] = potential(mesh.arc_from(a), slot[a]);
    arc_head[a] = potential(mesh.arc_to(a), slot[a]);
    if (negative[a]) std::swap(arc_tail[a], arc_head[a]);
  }
  potentials.tail_.resize(bundles.num_bundles());
  potentials.head_.resize(bundles.num_bundles());
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    const ArcId first = bundles.arcs(b).front();
    for (const ArcId a : bundles.arcs(b)) {
      if (arc_tail[a] != arc_tail[first] || arc_head[a] != arc_head[first]) return std::nullopt;
    }
    potentials.tail_[b] = arc_tail[first];
    potentials.head_[b] = arc_head[first];
  }
  // Every consistency row must vanish identically on potential differences.
  std::vector<LinearTerm> terms;
  for (int r = 0; r < consistency.num_rows(); ++r) {
    terms.clear();
    for (const LinearTerm& t : consistency.row(r)) {
      terms.push_back({arc_head[t.var], t.coef});
      terms.push_back({arc_tail[t.var], -t.coef});
    }
    MergeRepeatedTerms(terms);
    if (!terms.empty()) return std::nullopt;
  }
  potentials.has_handles_ = FirstBettiNumber(mesh) != 0;
  return potentials;
}

}  // namespace ispq
