// SPDX-License-Identifier: Apache-2.0
#include "core/simple_constraints.h"

#include <algorithm>

#include "core/block_extents.h"

namespace ispq {
namespace {

// Row over the given arcs, each with coefficient +1 times its multiplicity.
SeparationRow SumRow(std::span<const ArcId> arcs, int64_t rhs) {
  SeparationRow row;
  row.rhs = rhs;
  for (ArcId a : arcs) {
    auto it = std::find_if(row.terms.begin(), row.terms.end(),
                           [a](const LinearTerm& t) { return t.var == a; });
    if (it != row.terms.end()) {
      ++it->coef;
    } else {
      row.terms.push_back({a, 1});
    }
  }
  return row;
}

}  // namespace

std::vector<SimpleRow> BuildSimpleRows(const TMesh& mesh,
                                       std::optional<int64_t> per_arc_lower_bound) {
  std::vector<SimpleRow> rows;
  if (per_arc_lower_bound) {
    for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
      rows.push_back(
          {SimpleRowKind::kArcLowerBound, a, -1, SeparationRow{{{a, 1}}, *per_arc_lower_bound}});
    }
  }
  std::vector<ArcId> arcs;
  for (EntityId e = 0; e < mesh.num_entities(); ++e) {
    if (mesh.entity_dim(e) != EntityDim::kLink) continue;
    arcs.clear();
    for (HalfarcId h : mesh.entity_halfarcs(e)) arcs.push_back(ArcOf(h));
    rows.push_back({SimpleRowKind::kLink, e, -1, SumRow(arcs, 1)});
  }
  // A region must not collapse completely: the distinct arcs of all its patches, ascending.
  for (EntityId e = 0; e < mesh.num_entities(); ++e) {
    if (mesh.entity_dim(e) != EntityDim::kRegion) continue;
    arcs.clear();
    for (PatchId p : mesh.entity_patches(e)) {
      for (HalfarcId h : mesh.patch_cycle(p)) arcs.push_back(ArcOf(h));
    }
    std::sort(arcs.begin(), arcs.end());
    arcs.erase(std::unique(arcs.begin(), arcs.end()), arcs.end());
    rows.push_back({SimpleRowKind::kRegion, e, -1, SumRow(arcs, 1)});
  }
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int axis = 0; axis < 3; ++axis) {
      rows.push_back(
          {SimpleRowKind::kBlockExtent, b, axis, SumRow(ExtentRowArcs(mesh, b, axis), 0)});
    }
  }
  return rows;
}

}  // namespace ispq
