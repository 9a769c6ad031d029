// SPDX-License-Identifier: Apache-2.0
#include "core/critical_entities.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace ispq {
namespace {

// Follows critical arcs from halfarc `first` through non-critical nodes until a critical node,
// `stop` (the start of a cycle) or a node without an unused critical arc.
CriticalEntity TraceLink(const TMesh& mesh, HalfarcId first, NodeId stop,
                         std::vector<uint8_t>& used) {
  CriticalEntity link;
  link.dim = EntityDim::kLink;
  link.node_from = mesh.tail(first);
  HalfarcId h = first;
  while (true) {
    link.halfarcs.push_back(h);
    used[ArcOf(h)] = 1;
    const NodeId at = mesh.head(h);
    link.node_to = at;
    if (at == stop || mesh.node_critical(at)) break;
    const auto outgoing = mesh.outgoing_halfarcs(at);
    const auto next = std::find_if(outgoing.begin(), outgoing.end(), [&](HalfarcId o) {
      return mesh.arc_critical(ArcOf(o)) && !used[ArcOf(o)];
    });
    if (next == outgoing.end()) break;
    h = *next;
  }
  return link;
}

// The region of critical patch `seed`: breadth-first across non-critical arcs.
CriticalEntity FloodRegion(const TMesh& mesh, PatchId seed, std::vector<uint8_t>& in_region) {
  CriticalEntity region;
  region.dim = EntityDim::kRegion;
  std::vector<PatchId> queue = {seed};
  in_region[seed] = 1;
  for (size_t i = 0; i < queue.size(); ++i) {
    for (HalfarcId h : mesh.patch_cycle(queue[i])) {
      const ArcId a = ArcOf(h);
      if (mesh.arc_critical(a)) {
        region.boundary_arcs.push_back(a);
        continue;
      }
      for (HalfpatchId hp : mesh.arc_halfpatches(a)) {
        const PatchId p = PatchOf(hp);
        if (mesh.patch_critical(p) && !in_region[p]) {
          in_region[p] = 1;
          queue.push_back(p);
        }
      }
    }
  }
  region.patches = std::move(queue);
  std::sort(region.patches.begin(), region.patches.end());
  std::sort(region.boundary_arcs.begin(), region.boundary_arcs.end());
  region.boundary_arcs.erase(std::unique(region.boundary_arcs.begin(), region.boundary_arcs.end()),
                             region.boundary_arcs.end());
  return region;
}

}  // namespace

std::vector<CriticalEntity> DeriveCriticalEntities(const TMesh& mesh) {
  std::vector<CriticalEntity> entities;
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    if (!mesh.node_critical(n)) continue;
    CriticalEntity node;
    node.node_from = node.node_to = n;
    entities.push_back(std::move(node));
  }
  std::vector<uint8_t> used(mesh.num_arcs(), 0);
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    if (!mesh.node_critical(n)) continue;
    for (HalfarcId h : mesh.outgoing_halfarcs(n)) {
      if (mesh.arc_critical(ArcOf(h)) && !used[ArcOf(h)]) {
        entities.push_back(TraceLink(mesh, h, kNoId, used));
      }
    }
  }
  // Critical arcs no critical node reaches form cycles, started at their lowest arc.
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    if (mesh.arc_critical(a) && !used[a]) {
      const HalfarcId first = HalfarcOf(a, false);
      entities.push_back(TraceLink(mesh, first, mesh.tail(first), used));
    }
  }
  std::vector<uint8_t> in_region(mesh.num_patches(), 0);
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    if (mesh.patch_critical(p) && !in_region[p])
      entities.push_back(FloodRegion(mesh, p, in_region));
  }
  return entities;
}

std::string DescribeCriticalEntity(const CriticalEntity& entity) {
  switch (entity.dim) {
    case EntityDim::kNode:
      return absl::StrCat("node ", entity.node_from);
    case EntityDim::kLink:
      return absl::StrCat("link ", entity.node_from, "->", entity.node_to, " [halfarcs ",
                          absl::StrJoin(entity.halfarcs, ","), "]");
    case EntityDim::kRegion:
      return absl::StrCat("region [patches ", absl::StrJoin(entity.patches, ","),
                          "; boundary arcs ", absl::StrJoin(entity.boundary_arcs, ","), "]");
  }
  return "unknown entity";
}

}  // namespace ispq
