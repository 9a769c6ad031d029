// SPDX-License-Identifier: Apache-2.0
#include "core/mesh_stats.h"

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/subproblems.h"

namespace ispq {

MeshStats ComputeMeshStats(const TMesh& mesh) {
  MeshStats s;
  s.blocks = mesh.num_blocks();
  s.patches = mesh.num_patches();
  s.arcs = mesh.num_arcs();
  s.nodes = mesh.num_nodes();
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) s.critical_nodes += mesh.node_critical(n);
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) s.critical_arcs += mesh.arc_critical(a);
  for (PatchId p = 0; p < mesh.num_patches(); ++p) s.critical_patches += mesh.patch_critical(p);
  s.critical_entities = mesh.num_entities();
  for (EntityId e = 0; e < mesh.num_entities(); ++e) {
    s.critical_links += mesh.entity_dim(e) == EntityDim::kLink;
    s.critical_regions += mesh.entity_dim(e) == EntityDim::kRegion;
  }
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  s.consistency_rows = consistency.num_rows();
  for (int r = 0; r < consistency.num_rows(); ++r) {
    s.reduced_consistency_rows += bundles.ToBundleTerms(consistency.row(r)).empty() ? 0 : 1;
  }
  s.bundles = bundles.num_bundles();
  s.subproblems = Subproblems(mesh, consistency, bundles).num_subproblems();
  return s;
}

}  // namespace ispq
