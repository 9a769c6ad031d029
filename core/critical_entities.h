// SPDX-License-Identifier: Apache-2.0
// The critical entities of a T-mesh, derived from its critical flags (proto/README.md, section
// Critical entities): every critical node; every critical link, a maximal chain of critical arcs
// between critical nodes (or a cycle of them); every critical region, a maximal set of critical
// patches connected across non-critical arcs.
//
// The separation search starts from these entities and the simple rows are built over them, so
// they are never taken from a request: the loader derives them and rejects a request whose list
// says otherwise. The order is upstream's (nodes ascending; links traced from critical nodes in
// outgoing-halfarc order, then cycles from their lowest arc; regions by lowest patch), which
// reproduces the lists of all shared and exported T-meshes exactly.
#ifndef ISPQ_CORE_CRITICAL_ENTITIES_H_
#define ISPQ_CORE_CRITICAL_ENTITIES_H_

#include <string>
#include <vector>

#include "core/tmesh.h"

namespace ispq {

struct CriticalEntity {
  EntityDim dim = EntityDim::kNode;
  NodeId node_from = kNoId;          // node and link entities; kNoId for regions
  NodeId node_to = kNoId;            // equals node_from for nodes and cyclic links
  std::vector<HalfarcId> halfarcs;   // links: the chain from node_from to node_to
  std::vector<PatchId> patches;      // regions: ascending
  std::vector<ArcId> boundary_arcs;  // regions: the critical arcs of their patches, ascending

  friend bool operator==(const CriticalEntity&, const CriticalEntity&) = default;
};

// Reads node, arc and patch criticality, outgoing halfarcs, patch cycles and arc halfpatches of
// `mesh` (nothing else, so the loader can call it before the entity lists exist). Every
// non-critical node must have 0 or 2 incident critical arcs (the criticality rules guarantee
// it); a chain that meets one with more stops there.
std::vector<CriticalEntity> DeriveCriticalEntities(const TMesh& mesh);

// "node 4", "link 3->7 [halfarcs 6,9]", "region [patches 2,5]": for error messages.
std::string DescribeCriticalEntity(const CriticalEntity& entity);

}  // namespace ispq

#endif  // ISPQ_CORE_CRITICAL_ENTITIES_H_
