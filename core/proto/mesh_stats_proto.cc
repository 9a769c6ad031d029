// SPDX-License-Identifier: Apache-2.0
#include "core/proto/mesh_stats_proto.h"

namespace ispq {

v1::MeshStats MeshStatsToProto(const MeshStats& stats) {
  v1::MeshStats proto;
  proto.set_blocks(stats.blocks);
  proto.set_patches(stats.patches);
  proto.set_arcs(stats.arcs);
  proto.set_nodes(stats.nodes);
  proto.set_critical_nodes(stats.critical_nodes);
  proto.set_critical_arcs(stats.critical_arcs);
  proto.set_critical_patches(stats.critical_patches);
  proto.set_critical_entities(stats.critical_entities);
  proto.set_critical_links(stats.critical_links);
  proto.set_critical_regions(stats.critical_regions);
  proto.set_consistency_rows(stats.consistency_rows);
  proto.set_reduced_consistency_rows(stats.reduced_consistency_rows);
  proto.set_bundles(stats.bundles);
  proto.set_subproblems(stats.subproblems);
  return proto;
}

}  // namespace ispq
