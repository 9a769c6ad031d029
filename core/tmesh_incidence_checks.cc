// SPDX-License-Identifier: Apache-2.0
#include "core/tmesh_incidence_checks.h"

#include <algorithm>
#include <vector>

#include "absl/strings/str_join.h"
#include "core/invalid_argument.h"
#include "core/status_macros.h"

namespace ispq {
namespace {

// Halfpatches listed by each block face the block; patches listed on a face lie on it.
absl::Status CheckBlockLists(const TMesh& mesh, BlockId b) {
  for (HalfpatchId hp : mesh.block_halfpatches(b)) {
    if (mesh.halfpatch_block(hp) != b) {
      return InvalidArgument("block ", b, ": lists halfpatch ", hp, " whose block is ",
                             mesh.halfpatch_block(hp));
    }
  }
  for (Dir side : kAllDirs) {
    for (PatchId p : mesh.block_face_patches(b, side)) {
      const int k = mesh.patch_block(p, 0) == b ? 0 : (mesh.patch_block(p, 1) == b ? 1 : -1);
      if (k < 0 || mesh.patch_face_side(p, k) != side) {
        return InvalidArgument("block ", b, ": face ", DirName(side), " lists patch ", p,
                               " which does not lie on that face of the block");
      }
    }
  }
  return absl::OkStatus();
}

// Each block of patch p lists the patch as a halfpatch and on the face the patch lies on.
absl::Status CheckListedByBlocks(const TMesh& mesh, PatchId p) {
  for (int k = 0; k < 2; ++k) {
    const BlockId b = mesh.patch_block(p, k);
    if (b == kNoId) continue;
    const auto hps = mesh.block_halfpatches(b);
    if (std::find(hps.begin(), hps.end(), 2 * p + k) == hps.end()) {
      return InvalidArgument("patch ", p, ": side ", k, " faces block ", b,
                             " but the block does not list halfpatch ", 2 * p + k);
    }
    const auto face = mesh.block_face_patches(b, mesh.patch_face_side(p, k));
    if (std::find(face.begin(), face.end(), p) == face.end()) {
      return InvalidArgument("patch ", p, ": lies on face ", DirName(mesh.patch_face_side(p, k)),
                             " of block ", b, " but that face does not list it");
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status CheckNodeArcIncidence(const TMesh& mesh) {
  std::vector<int> listed(mesh.num_halfarcs(), 0);
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    for (HalfarcId h : mesh.outgoing_halfarcs(n)) {
      if (mesh.tail(h) != n) {
        return InvalidArgument("node ", n, ": outgoing halfarc ", h, " starts at node ",
                               mesh.tail(h));
      }
      if (listed[h]++) {
        return InvalidArgument("node ", n, ": outgoing halfarc ", h, " listed twice");
      }
    }
  }
  for (HalfarcId h = 0; h < mesh.num_halfarcs(); ++h) {
    if (!listed[h]) {
      return InvalidArgument("node ", mesh.tail(h), ": outgoing halfarc ", h, " is missing");
    }
  }
  return absl::OkStatus();
}

absl::Status CheckArcPatchIncidence(const TMesh& mesh) {
  std::vector<std::vector<HalfpatchId>> expected(mesh.num_arcs());
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    for (HalfarcId h : mesh.patch_cycle(p)) expected[ArcOf(h)].push_back(2 * p + (h & 1));
  }
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    std::vector<HalfpatchId> listed(mesh.arc_halfpatches(a).begin(), mesh.arc_halfpatches(a).end());
    std::sort(listed.begin(), listed.end());
    std::sort(expected[a].begin(), expected[a].end());
    if (listed != expected[a]) {
      return InvalidArgument("arc ", a, ": halfpatches [", absl::StrJoin(listed, ","),
                             "] differ from the patches whose cycles contain it [",
                             absl::StrJoin(expected[a], ","), "]");
    }
  }
  return absl::OkStatus();
}

absl::Status CheckPatchBlockIncidence(const TMesh& mesh) {
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) ISPQ_RETURN_IF_ERROR(CheckBlockLists(mesh, b));
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    ISPQ_RETURN_IF_ERROR(CheckListedByBlocks(mesh, p));
  }
  return absl::OkStatus();
}

absl::Status CheckArcBlocks(const TMesh& mesh) {
  std::vector<std::vector<BlockId>> listed_by_blocks(mesh.num_arcs());
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (const BlockArc& ba : mesh.block_arcs(b)) listed_by_blocks[ba.arc].push_back(b);
  }
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    std::vector<BlockId> around(mesh.arc_blocks(a).begin(), mesh.arc_blocks(a).end());
    std::sort(around.begin(), around.end());
    if (around != listed_by_blocks[a]) {
      return InvalidArgument("arc ", a, ": the blocks around it [", absl::StrJoin(around, ","),
                             "] differ from the blocks listing it in arcsByDir [",
                             absl::StrJoin(listed_by_blocks[a], ","), "]");
    }
  }
  return absl::OkStatus();
}

}  // namespace ispq
