// SPDX-License-Identifier: Apache-2.0
#include "core/tmesh_element_checks.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "core/invalid_argument.h"
#include "core/resolution_levels.h"

namespace ispq {

absl::Status CheckSizes(const TMeshSizes& sizes) {
  // Counts are bounded by the message itself; halfarc and halfpatch ids must fit in int32.
  constexpr int kMaxElements = std::numeric_limits<int32_t>::max() / 2;
  const std::pair<const char*, int> counts[] = {{"nodes", sizes.nodes},
                                                {"arcs", sizes.arcs},
                                                {"patches", sizes.patches},
                                                {"blocks", sizes.blocks}};
  for (const auto& [what, count] : counts) {
    if (count == 0) return InvalidArgument("the mesh has no ", what);
    if (count > kMaxElements) return InvalidArgument("the mesh has too many ", what, ": ", count);
  }
  return absl::OkStatus();
}

absl::Status CheckNode(NodeId n, const NodeInput& node, const FeaturesPresent& present) {
  if (node.feature && !present.nodes) {
    return InvalidArgument("node ", n, ": marked feature but featuresPresent.nodes is false");
  }
  return absl::OkStatus();
}

absl::Status CheckArc(ArcId a, const ArcInput& arc, const FeaturesPresent& present) {
  if (arc.from == arc.to) return InvalidArgument("arc ", a, ": starts and ends at node ", arc.to);
  if (!std::isfinite(arc.length) || arc.length <= 0) {
    return InvalidArgument("arc ", a, ": length ", arc.length, " is not a positive finite number");
  }
  if (arc.singular < -4 || arc.singular > 4) {
    return InvalidArgument("arc ", a, ": singular mark ", arc.singular, " is out of range -4..4");
  }
  if (arc.critical != (arc.singular != 0 || arc.feature)) {
    return InvalidArgument("arc ", a, ": critical flag ", arc.critical,
                           " contradicts singular != 0 || feature");
  }
  if (arc.feature && !present.arcs) {
    return InvalidArgument("arc ", a, ": marked feature but featuresPresent.arcs is false");
  }
  if (arc.halfpatches.empty()) return InvalidArgument("arc ", a, ": lies on no patch");
  return absl::OkStatus();
}

absl::Status CheckBlock(BlockId b, const BlockInput& block) {
  for (size_t i = 1; i < block.arcs.size(); ++i) {
    if (block.arcs[i].arc == block.arcs[i - 1].arc) {
      return InvalidArgument("block ", b, ": arc ", block.arcs[i].arc,
                             " appears twice in arcsByDir");
    }
  }
  for (size_t i = 1; i < block.node_uvw.size(); ++i) {
    if (block.node_uvw[i].node == block.node_uvw[i - 1].node) {
      return InvalidArgument("block ", b, ": node ", block.node_uvw[i].node,
                             " appears twice in nodeUvw");
    }
  }
  return absl::OkStatus();
}

absl::Status CheckLevel(int index, const Level& level, std::span<const double> arc_lengths) {
  if (!IsLevelPercent(level.percent)) {
    return InvalidArgument("level ", index, ": percent ", level.percent,
                           " is not one of the format's levels");
  }
  const double expected = *ScalingForPercent(arc_lengths, level.percent);
  if (!std::isfinite(level.scaling) || std::abs(level.scaling - expected) > 1e-9 * expected) {
    return InvalidArgument("level ", index, ": scaling ", level.scaling, " for ", level.percent,
                           "% should be ", expected);
  }
  return absl::OkStatus();
}

}  // namespace ispq
