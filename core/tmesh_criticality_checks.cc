// SPDX-License-Identifier: Apache-2.0
#include "core/tmesh_criticality_checks.h"

#include <cstdint>
#include <vector>

#include "core/arc_singularity.h"
#include "core/invalid_argument.h"

namespace ispq {
namespace {

// Which arcs and nodes lie on the cycle of some feature patch.
struct OnFeaturePatch {
  std::vector<uint8_t> arcs, nodes;
};

OnFeaturePatch MarkFeaturePatchCycles(const TMesh& mesh) {
  OnFeaturePatch on{std::vector<uint8_t>(mesh.num_arcs(), 0),
                    std::vector<uint8_t>(mesh.num_nodes(), 0)};
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    if (!mesh.patch_feature(p)) continue;
    for (HalfarcId h : mesh.patch_cycle(p)) {
      on.arcs[ArcOf(h)] = 1;
      on.nodes[mesh.tail(h)] = 1;
    }
  }
  return on;
}

// The marks of the arcs at a node that the critical-node rules count.
struct IncidentMarks {
  int singular = 0, feature = 0;
  bool singular_non_feature = false, singular_off_feature_patches = false;
};

IncidentMarks CountIncidentMarks(const TMesh& mesh, NodeId n, const OnFeaturePatch& on) {
  IncidentMarks marks;
  for (HalfarcId h : mesh.outgoing_halfarcs(n)) {
    const ArcId a = ArcOf(h);
    if (mesh.arc_feature(a)) ++marks.feature;
    if (mesh.arc_singular(a) != 0) {
      ++marks.singular;
      if (!mesh.arc_feature(a)) marks.singular_non_feature = true;
      if (!on.arcs[a]) marks.singular_off_feature_patches = true;
    }
  }
  return marks;
}

bool CriticalByRules(const IncidentMarks& m, bool node_feature, bool on_feature_patch,
                     const FeaturesPresent& present) {
  bool critical = (m.singular != 0 && m.singular != 2) || node_feature;
  if (present.arcs) {
    critical = critical || (m.feature != 0 && m.feature != 2) ||
               (m.feature == 2 && m.singular_non_feature);
  }
  if (present.patches) {
    critical = critical || (m.feature == 0 && m.singular == 2 && on_feature_patch &&
                            m.singular_off_feature_patches);
  }
  return critical;
}

const char* SingularTypeName(SingularType type) {
  switch (type) {
    case SingularType::kRegular:
      return "REGULAR";
    case SingularType::kSemiSingular:
      return "SEMI_SINGULAR";
    case SingularType::kSingular:
      return "SINGULAR";
  }
  return "?";
}

const char* FeatureTypeName(FeatureType type) {
  switch (type) {
    case FeatureType::kRegular:
      return "REGULAR";
    case FeatureType::kSemiFeature:
      return "SEMI_FEATURE";
    case FeatureType::kFeature:
      return "FEATURE";
    case FeatureType::kSemiFeatureSingularBranch:
      return "SEMI_FEATURE_SINGULAR_BRANCH";
  }
  return "?";
}

SingularType SingularTypeOf(const IncidentMarks& m) {
  if (m.singular == 0) return SingularType::kRegular;
  return m.singular == 2 ? SingularType::kSemiSingular : SingularType::kSingular;
}

// The branches are the two ways CriticalByRules makes a node critical through feature markers
// without making it FEATURE; feature arcs and patches only exist where the source has them.
FeatureType FeatureTypeOf(const IncidentMarks& m, bool node_feature, bool on_feature_patch) {
  if (node_feature || (m.feature != 0 && m.feature != 2)) return FeatureType::kFeature;
  if (m.feature == 2) {
    return m.singular_non_feature ? FeatureType::kSemiFeatureSingularBranch
                                  : FeatureType::kSemiFeature;
  }
  if (m.singular == 2 && on_feature_patch && m.singular_off_feature_patches) {
    return FeatureType::kSemiFeatureSingularBranch;
  }
  return FeatureType::kRegular;
}

}  // namespace

absl::Status CheckArcSingularity(const TMesh& mesh) {
  const std::vector<int> quarter_turns = QuarterTurnsAroundArcs(mesh);
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const bool on_boundary = ArcOnBoundary(mesh, a);
    if (mesh.arc_boundary(a) != on_boundary) {
      return InvalidArgument("arc ", a, ": boundary flag ", mesh.arc_boundary(a), " but it ",
                             on_boundary ? "lies" : "does not lie", " on a boundary patch");
    }
    if (SingularByQuarterTurns(quarter_turns[a], on_boundary) != (mesh.arc_singular(a) != 0)) {
      return InvalidArgument("arc ", a, ": singular mark ", mesh.arc_singular(a),
                             " contradicts the ", quarter_turns[a],
                             " quarter turns of the blocks around this ",
                             on_boundary ? "boundary" : "interior", " arc (singular iff not ",
                             on_boundary ? 2 : 4, ")");
    }
  }
  return absl::OkStatus();
}

absl::Status CheckCriticalNodes(const TMesh& mesh, const FeaturesPresent& present) {
  const OnFeaturePatch on = MarkFeaturePatchCycles(mesh);
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    const IncidentMarks marks = CountIncidentMarks(mesh, n, on);
    const bool critical = CriticalByRules(marks, mesh.node_feature(n), on.nodes[n], present);
    if (critical != mesh.node_critical(n)) {
      return InvalidArgument("node ", n, ": critical flag ", mesh.node_critical(n),
                             " contradicts the criticality rules (", marks.singular,
                             " singular and ", marks.feature, " feature arcs)");
    }
  }
  return absl::OkStatus();
}

absl::Status CheckNodeTypes(const TMesh& mesh, std::span<const NodeTypes> declared) {
  const OnFeaturePatch on = MarkFeaturePatchCycles(mesh);
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    const IncidentMarks marks = CountIncidentMarks(mesh, n, on);
    const SingularType singular = SingularTypeOf(marks);
    if (declared[n].singular != singular) {
      return InvalidArgument("node ", n, ": singularType ", SingularTypeName(declared[n].singular),
                             " but ", marks.singular, " singular arcs meet there (",
                             SingularTypeName(singular), ")");
    }
    const FeatureType feature = FeatureTypeOf(marks, mesh.node_feature(n), on.nodes[n]);
    if (declared[n].feature != feature) {
      return InvalidArgument("node ", n, ": featureType ", FeatureTypeName(declared[n].feature),
                             " but its marks make it ", FeatureTypeName(feature), " (",
                             marks.feature, " feature and ", marks.singular, " singular arcs, ",
                             mesh.node_feature(n) ? "a" : "not a", " feature node)");
    }
  }
  return absl::OkStatus();
}

absl::Status CheckListedCriticalEntities(std::span<const CriticalEntity> derived,
                                         std::span<const CriticalEntity> listed) {
  if (listed.empty()) return absl::OkStatus();
  for (size_t e = 0; e < listed.size(); ++e) {
    if (e >= derived.size()) {
      return InvalidArgument("critical entity ", e, ": the mesh has only ", derived.size(),
                             " critical entities, the request lists ", listed.size());
    }
    if (!(listed[e] == derived[e])) {
      return InvalidArgument("critical entity ", e, ": the mesh makes it ",
                             DescribeCriticalEntity(derived[e]), ", the request says ",
                             DescribeCriticalEntity(listed[e]));
    }
  }
  if (listed.size() < derived.size()) {
    return InvalidArgument("critical entity ", listed.size(),
                           ": missing from the request (the mesh makes it ",
                           DescribeCriticalEntity(derived[listed.size()]), ")");
  }
  return absl::OkStatus();
}

}  // namespace ispq
