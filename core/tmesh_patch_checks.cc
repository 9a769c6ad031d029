// SPDX-License-Identifier: Apache-2.0
#include "core/tmesh_patch_checks.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "core/invalid_argument.h"
#include "core/status_macros.h"

namespace ispq {
namespace {

absl::Status CheckBlocksAndFlags(PatchId p, const PatchInput& patch,
                                 const FeaturesPresent& present) {
  const int boundary_sides = (patch.blocks[0] == kNoId) + (patch.blocks[1] == kNoId);
  if (boundary_sides == 2) return InvalidArgument("patch ", p, ": has no block on either side");
  if (patch.blocks[0] == patch.blocks[1]) {
    return InvalidArgument("patch ", p, ": block ", patch.blocks[0],
                           " is on both sides (self-adjacent blocks are not supported)");
  }
  if (patch.boundary != (boundary_sides == 1)) {
    return InvalidArgument("patch ", p, ": boundary flag ", patch.boundary,
                           " contradicts its blocks");
  }
  if (patch.feature && !present.patches) {
    return InvalidArgument("patch ", p, ": marked feature but featuresPresent.patches is false");
  }
  if (patch.critical != (patch.boundary || patch.feature)) {
    return InvalidArgument("patch ", p, ": critical flag contradicts boundary || feature");
  }
  if (boundary_sides == 1 && !patch.rotation.IsIdentity()) {
    return InvalidArgument("patch ", p, ": boundary patch with a non-identity transition");
  }
  return absl::OkStatus();
}

// A closed chain of distinct arcs, and the reference block is the first existing block.
absl::Status CheckCycle(PatchId p, const PatchInput& patch, const TMesh& mesh) {
  const std::span<const HalfarcId> cycle = patch.cycle;
  const int size = static_cast<int>(cycle.size());
  if (size < 4) {
    return InvalidArgument("patch ", p, ": cycle has ", size, " halfarcs, at least 4 needed");
  }
  std::vector<ArcId> arcs;
  for (int i = 0; i < size; ++i) {
    const HalfarcId h = cycle[i];
    const HalfarcId next = cycle[(i + 1) % size];
    if (mesh.head(h) != mesh.tail(next)) {
      return InvalidArgument("patch ", p, ": cycle is not closed: halfarc ", h, " ends at node ",
                             mesh.head(h), " but halfarc ", next, " starts at node ",
                             mesh.tail(next));
    }
    arcs.push_back(ArcOf(h));
  }
  std::sort(arcs.begin(), arcs.end());
  if (std::adjacent_find(arcs.begin(), arcs.end()) != arcs.end()) {
    return InvalidArgument("patch ", p, ": cycle uses an arc twice");
  }
  const BlockId expected_ref = patch.blocks[0] != kNoId ? patch.blocks[0] : patch.blocks[1];
  if (patch.ref_block != expected_ref) {
    return InvalidArgument("patch ", p, ": refBlock ", patch.ref_block, " should be ",
                           expected_ref);
  }
  return absl::OkStatus();
}

// A side is a non-empty run of consecutive cycle halfarcs, with a direction of its own.
absl::Status CheckSide(PatchId p, const PatchSideInput& side, std::span<const HalfarcId> cycle,
                       DirSet& dirs) {
  if (dirs & DirBit(side.dir)) {
    return InvalidArgument("patch ", p, ": direction ", DirName(side.dir), " used by two sides");
  }
  dirs |= DirBit(side.dir);
  if (side.halfarcs.empty()) {
    return InvalidArgument("patch ", p, ": side ", DirName(side.dir), " is empty");
  }
  const auto start = std::find(cycle.begin(), cycle.end(), side.halfarcs[0]);
  if (start == cycle.end()) {
    return InvalidArgument("patch ", p, ": side ", DirName(side.dir), " halfarc ", side.halfarcs[0],
                           " is not in the cycle");
  }
  const size_t offset = start - cycle.begin();
  for (size_t j = 0; j < side.halfarcs.size(); ++j) {
    if (side.halfarcs.size() > cycle.size() ||
        cycle[(offset + j) % cycle.size()] != side.halfarcs[j]) {
      return InvalidArgument("patch ", p, ": side ", DirName(side.dir),
                             " is not a contiguous run of the cycle");
    }
  }
  return absl::OkStatus();
}

// Four sides that partition the cycle into two pairs of opposite directions.
absl::Status CheckSides(PatchId p, const PatchInput& patch) {
  DirSet dirs = 0;
  size_t total = 0;
  for (const PatchSideInput& side : patch.sides) {
    ISPQ_RETURN_IF_ERROR(CheckSide(p, side, patch.cycle, dirs));
  }
  for (const PatchSideInput& side : patch.sides) total += side.halfarcs.size();
  if (total != patch.cycle.size()) {
    return InvalidArgument("patch ", p, ": sides do not partition the cycle");
  }
  for (int axis = 0; axis < 3; ++axis) {
    const DirSet on_axis = dirs & AxisBits(axis);
    if (on_axis != 0 && on_axis != AxisBits(axis)) {
      return InvalidArgument("patch ", p, ": sides are not two pairs of opposite directions");
    }
  }
  return absl::OkStatus();
}

double SideLength(std::span<const HalfarcId> halfarcs, const TMesh& mesh) {
  double sum = 0;
  for (HalfarcId h : halfarcs) sum += mesh.arc_length(ArcOf(h));
  return sum;
}

// Opposite sides have equal continuous length: the patch is a rectangle in its block's frame.
absl::Status CheckOppositeSides(PatchId p, const PatchInput& patch, const TMesh& mesh,
                                double length_tolerance) {
  for (const PatchSideInput& side : patch.sides) {
    if (IsNegative(side.dir)) continue;
    for (const PatchSideInput& opposite : patch.sides) {
      if (opposite.dir != Opposite(side.dir)) continue;
      const double a = SideLength(side.halfarcs, mesh), b = SideLength(opposite.halfarcs, mesh);
      if (std::abs(a - b) > length_tolerance * std::max({1.0, a, b})) {
        return InvalidArgument("patch ", p, ": side ", DirName(side.dir), " has continuous length ",
                               a, " but the opposite side ", DirName(opposite.dir), " has ", b);
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status CheckPatch(PatchId p, const PatchInput& patch, const TMesh& mesh,
                        const FeaturesPresent& present, double length_tolerance) {
  ISPQ_RETURN_IF_ERROR(CheckBlocksAndFlags(p, patch, present));
  ISPQ_RETURN_IF_ERROR(CheckCycle(p, patch, mesh));
  ISPQ_RETURN_IF_ERROR(CheckSides(p, patch));
  return CheckOppositeSides(p, patch, mesh, length_tolerance);
}

}  // namespace ispq
