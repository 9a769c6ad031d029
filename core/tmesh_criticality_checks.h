// SPDX-License-Identifier: Apache-2.0
// Rules about what is critical (proto/README.md, sections Arcs, Criticality and Critical entities):
// an arc's boundary flag and whether its singular mark is non-zero follow from the blocks around it
// (core/arc_singularity.h); a node's critical flag follows from the marks of its arcs and patches;
// and a list of critical entities that comes with the mesh must be the one the mesh makes
// (core/critical_entities.h).
//
// The separation certificate rests on these flags, so they are recomputed and compared instead of
// trusted: a mismatch means the mesh was built by different rules. TMeshBuilder runs them after
// the incidence and frame checks, once the arc -> blocks adjacency exists. Failures are
// INVALID_ARGUMENT naming the element and both verdicts.
#ifndef ISPQ_CORE_TMESH_CRITICALITY_CHECKS_H_
#define ISPQ_CORE_TMESH_CRITICALITY_CHECKS_H_

#include <span>

#include "absl/status/status.h"
#include "core/critical_entities.h"
#include "core/tmesh.h"
#include "core/tmesh_input.h"

namespace ispq {

absl::Status CheckArcSingularity(const TMesh& mesh);

// The critical-node rules (proto/README.md, section Criticality); which of them apply depends on
// the kinds of feature markers the source had.
absl::Status CheckCriticalNodes(const TMesh& mesh, const FeaturesPresent& present);

// `listed` (a request's list; empty when it sends none) equals `derived` entity by entity.
absl::Status CheckListedCriticalEntities(std::span<const CriticalEntity> derived,
                                         std::span<const CriticalEntity> listed);

// The two classifications a node's source states beside its flags.
struct NodeTypes {
  SingularType singular = SingularType::kRegular;
  FeatureType feature = FeatureType::kRegular;
};

// Each node's stated types (`declared`, one per node) are the ones its arcs and patches make.
// singularType counts the singular arcs at the node: none REGULAR, two SEMI_SINGULAR, any other
// number SINGULAR. featureType is FEATURE for a feature node or one with a number of feature arcs
// other than 0 or 2; SEMI_FEATURE_SINGULAR_BRANCH for two feature arcs and a non-feature singular
// one, or for no feature arc, two singular arcs, a feature patch through the node and a singular
// arc on no feature patch; SEMI_FEATURE for two feature arcs otherwise; REGULAR otherwise. With
// CheckCriticalNodes this makes a node critical exactly when it is SINGULAR, FEATURE or
// SEMI_FEATURE_SINGULAR_BRANCH, so the flags and the types cannot tell different stories.
absl::Status CheckNodeTypes(const TMesh& mesh, std::span<const NodeTypes> declared);

}  // namespace ispq

#endif  // ISPQ_CORE_TMESH_CRITICALITY_CHECKS_H_
