// SPDX-License-Identifier: Apache-2.0
#include "core/tmesh_frame_checks.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/invalid_argument.h"
#include "core/status_macros.h"

namespace ispq {
namespace {

// Every cycle arc is on each block of the patch and runs within the face, not across it.
absl::Status CheckCycleInFaces(const TMesh& mesh, PatchId p) {
  for (int k = 0; k < 2; ++k) {
    const BlockId b = mesh.patch_block(p, k);
    if (b == kNoId) continue;
    for (HalfarcId h : mesh.patch_cycle(p)) {
      const std::optional<Dir> d = mesh.HalfarcDirInBlock(h, b);
      if (!d) {
        return InvalidArgument("patch ", p, ": arc ", ArcOf(h), " of its cycle is not on block ",
                               b);
      }
      if (AxisOf(*d) == AxisOf(mesh.patch_face_side(p, k))) {
        return InvalidArgument("patch ", p, ": arc ", ArcOf(h), " runs across face ",
                               DirName(mesh.patch_face_side(p, k)), " of block ", b);
      }
    }
  }
  return absl::OkStatus();
}

// a × b for two axis directions; nullopt when they are parallel.
std::optional<Dir> Cross(Dir a, Dir b) {
  const int i = AxisOf(a), j = AxisOf(b);
  if (i == j) return std::nullopt;
  // e_i × e_j = +e_k when (i, j, k) is a cyclic order of the axes, -e_k otherwise.
  const bool cyclic = (j - i + 3) % 3 == 1;
  return MakeDir(3 - i - j, (IsNegative(a) != IsNegative(b)) == cyclic);
}

// Each halfpatch's cycle turns, at every corner, about the normal into its block (the
// right-hand rule): the halfpatch faces its block, and a cycle that turned the other way anywhere
// would not bound a rectangle. The arcs are known to lie in the face (CheckCycleInFaces), so
// every turn is about the face's normal, one way or the other.
absl::Status CheckCycleOrientation(const TMesh& mesh, PatchId p) {
  for (int k = 0; k < 2; ++k) {
    const BlockId b = mesh.patch_block(p, k);
    if (b == kNoId) continue;
    const HalfpatchId hp = 2 * p + k;
    const Dir inward = Opposite(mesh.patch_face_side(p, k));
    const int size = mesh.halfpatch_cycle_size(hp);
    for (int i = 0; i < size; ++i) {
      const HalfarcId h = mesh.HalfpatchCycleAt(hp, i);
      const HalfarcId next = mesh.HalfpatchCycleAt(hp, (i + 1) % size);
      const std::optional<Dir> turn =
          Cross(*mesh.HalfarcDirInBlock(h, b), *mesh.HalfarcDirInBlock(next, b));
      if (turn && *turn != inward) {
        return InvalidArgument("patch ", p, ": the cycle of halfpatch ", hp, " turns about ",
                               DirName(*turn), " at node ", mesh.head(h),
                               " where it must turn about ", DirName(inward),
                               ", the normal into block ", b);
      }
    }
  }
  return absl::OkStatus();
}

absl::Status CheckSideDirections(const TMesh& mesh, PatchId p) {
  const BlockId ref = mesh.patch_ref_block(p);
  for (int i = 0; i < 4; ++i) {
    const PatchSide side = mesh.patch_side(p, i);
    for (HalfarcId h : side.halfarcs) {
      if (mesh.HalfarcDirInBlock(h, ref) != side.dir) {
        return InvalidArgument("patch ", p, ": halfarc ", h, " of side ", DirName(side.dir),
                               " does not run along ", DirName(side.dir), " in block ", ref);
      }
    }
  }
  return absl::OkStatus();
}

// The rotation maps each cycle arc's direction in the first block to its direction in the second.
absl::Status CheckTransition(const TMesh& mesh, PatchId p) {
  const BlockId b0 = mesh.patch_block(p, 0), b1 = mesh.patch_block(p, 1);
  if (b0 == kNoId || b1 == kNoId) return absl::OkStatus();
  const Rotation r = mesh.patch_rotation(p);
  for (HalfarcId h : mesh.patch_cycle(p)) {
    if (r.Apply(*mesh.HalfarcDirInBlock(h, b0)) != *mesh.HalfarcDirInBlock(h, b1)) {
      return InvalidArgument("patch ", p, ": transition does not map the direction of arc ",
                             ArcOf(h), " in block ", b0, " to its direction in block ", b1);
    }
  }
  return absl::OkStatus();
}

absl::Status CheckEdgeChain(const TMesh& mesh, BlockId b, int code,
                            std::span<const HalfarcId> halfarcs) {
  const int axis = EdgeAxis(code);
  const int first = axis == 0 ? 1 : 0, second = axis == 2 ? 1 : 2;
  const int low_corner = (((code & 1) ? 1 : 0) << first) | (((code & 2) ? 1 : 0) << second);
  const int high_corner = low_corner | (1 << axis);
  NodeId at = mesh.block_corner(b, low_corner);
  for (HalfarcId h : halfarcs) {
    if (mesh.tail(h) != at || mesh.HalfarcDirInBlock(h, b) != MakeDir(axis, false)) {
      return InvalidArgument("block ", b, ": edge ", EdgeName(code),
                             " is not a chain along its positive axis (at arc ", ArcOf(h), ")");
    }
    at = mesh.head(h);
  }
  if (at != mesh.block_corner(b, high_corner)) {
    return InvalidArgument("block ", b, ": edge ", EdgeName(code),
                           " does not end at its corner node ", mesh.block_corner(b, high_corner));
  }
  return absl::OkStatus();
}

const BlockNodeUvw* FindUvw(const TMesh& mesh, BlockId b, NodeId n) {
  const auto list = mesh.block_node_uvw(b);
  const auto it = std::lower_bound(list.begin(), list.end(), n,
                                   [](const BlockNodeUvw& e, NodeId id) { return e.node < id; });
  return it != list.end() && it->node == n ? &*it : nullptr;
}

absl::Status CheckArcCoordinates(const TMesh& mesh, BlockId b, const BlockArc& ba,
                                 double length_tolerance) {
  const BlockNodeUvw* from = FindUvw(mesh, b, mesh.arc_from(ba.arc));
  const BlockNodeUvw* to = FindUvw(mesh, b, mesh.arc_to(ba.arc));
  if (!from || !to) {
    return InvalidArgument("block ", b, ": nodeUvw lacks an endpoint of arc ", ba.arc);
  }
  const double length = mesh.arc_length(ba.arc);
  double scale = 1.0;
  for (int i = 0; i < 3; ++i) {
    scale = std::max({scale, std::abs(from->uvw[i]), std::abs(to->uvw[i])});
  }
  for (int i = 0; i < 3; ++i) {
    const double expected = i == AxisOf(ba.dir) ? SignOf(ba.dir) * length : 0.0;
    if (std::abs(to->uvw[i] - from->uvw[i] - expected) > length_tolerance * scale) {
      return InvalidArgument("block ", b, ": arc ", ba.arc, " of length ", length, " along ",
                             DirName(ba.dir), " does not match the coordinates of its nodes");
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status CheckPatchFrames(const TMesh& mesh) {
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    ISPQ_RETURN_IF_ERROR(CheckCycleInFaces(mesh, p));
    ISPQ_RETURN_IF_ERROR(CheckCycleOrientation(mesh, p));
    ISPQ_RETURN_IF_ERROR(CheckSideDirections(mesh, p));
    ISPQ_RETURN_IF_ERROR(CheckTransition(mesh, p));
  }
  return absl::OkStatus();
}

absl::Status CheckBlockEdgeChains(const TMesh& mesh, const FlatLists<HalfarcId>& edge_halfarcs,
                                  std::span<const int8_t> edge_order) {
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int i = 0; i < kNumEdges; ++i) {
      const int code = edge_order[kNumEdges * b + i];
      ISPQ_RETURN_IF_ERROR(CheckEdgeChain(mesh, b, code, edge_halfarcs[kNumEdges * b + code]));
    }
  }
  return absl::OkStatus();
}

absl::Status CheckBlockCoordinates(const TMesh& mesh, double length_tolerance) {
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (const BlockArc& ba : mesh.block_arcs(b)) {
      ISPQ_RETURN_IF_ERROR(CheckArcCoordinates(mesh, b, ba, length_tolerance));
    }
  }
  return absl::OkStatus();
}

}  // namespace ispq
