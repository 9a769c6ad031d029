// SPDX-License-Identifier: Apache-2.0
// Validation of T-mesh messages: every real file is accepted, and a table of corruptions, each
// generated from a real file, is rejected with a message that names the offending element.
#include "core/proto/tmesh_from_proto.h"

#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <string>

#include "core/proto/tmesh_from_wire.h"
#include "gmock/gmock.h"
#include "google/protobuf/io/zero_copy_stream_impl_lite.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

// A real mesh with interior patches and non-identity transitions.
const v1::TMesh& Tetrahedron() {
  static const v1::TMesh* const kMesh = new v1::TMesh(
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s04u_tetrahedron.tmesh.json")));
  return *kMesh;
}

int FirstNode(const v1::TMesh& m, const std::function<bool(const v1::Node&)>& predicate) {
  for (int n = 0; n < m.nodes_size(); ++n) {
    if (predicate(m.nodes(n))) return n;
  }
  return -1;
}

int FirstInteriorPatch(const v1::TMesh& m, bool non_identity) {
  for (int p = 0; p < m.patches_size(); ++p) {
    const auto& patch = m.patches(p);
    const bool identity = patch.transition().rotation(0) == 1 &&
                          patch.transition().rotation(1) == 2 &&
                          patch.transition().rotation(2) == 3;
    if (patch.blocks(0) >= 0 && patch.blocks(1) >= 0 && identity != non_identity) return p;
  }
  return -1;
}

// Index of side `dir` in a patch's halfarcsByDir.
v1::DirectedHalfarcs* SideOf(v1::Patch* patch, v1::UVWDir dir) {
  for (auto& side : *patch->mutable_halfarcs_by_dir()) {
    if (side.dir() == dir) return &side;
  }
  return nullptr;
}

struct Corruption {
  std::string name;
  std::function<void(v1::TMesh&)> mutate;
  std::string expected;  // substring of the error, naming the element
};

constexpr int32_t kHugeId = std::numeric_limits<int32_t>::max();

std::vector<Corruption> Corruptions() {
  const v1::TMesh& m = Tetrahedron();
  const int interior = FirstInteriorPatch(m, /*non_identity=*/false);
  const int rotated = FirstInteriorPatch(m, /*non_identity=*/true);
  const std::string interior_name = "patch " + std::to_string(interior) + ":";
  const std::string rotated_name = "patch " + std::to_string(rotated) + ":";
  const int singular_node = FirstNode(
      m, [](const v1::Node& n) { return n.singular_type() == v1::SingularType::SINGULAR; });
  const int semi_feature_node = FirstNode(
      m, [](const v1::Node& n) { return n.feature_type() == v1::FeatureType::SEMI_FEATURE; });
  return {
      {"empty mesh", [](v1::TMesh& t) { t.clear_nodes(); }, "the mesh has no nodes"},
      {"no blocks", [](v1::TMesh& t) { t.clear_blocks(); }, "the mesh has no blocks"},
      {"format version", [](v1::TMesh& t) { t.set_format_version(2); }, "formatVersion is 2"},
      {"arc from huge id", [](v1::TMesh& t) { t.mutable_arcs(3)->set_from(kHugeId); },
       "arc 3: node 'from' 2147483647 does not exist"},
      {"arc to negative", [](v1::TMesh& t) { t.mutable_arcs(4)->set_to(-5); },
       "arc 4: node 'to' -5 does not exist"},
      {"arc self loop", [](v1::TMesh& t) { t.mutable_arcs(5)->set_to(t.arcs(5).from()); },
       "arc 5: starts and ends"},
      {"arc length NaN", [](v1::TMesh& t) { t.mutable_arcs(6)->set_length(std::nan("")); },
       "arc 6: length nan"},
      {"arc length negative", [](v1::TMesh& t) { t.mutable_arcs(7)->set_length(-1.0); },
       "arc 7: length -1"},
      {"arc length infinite",
       [](v1::TMesh& t) { t.mutable_arcs(8)->set_length(std::numeric_limits<double>::infinity()); },
       "arc 8: length inf"},
      {"arc critical flag",
       [](v1::TMesh& t) {
         for (auto& arc : *t.mutable_arcs()) {
           if (!arc.critical()) {
             arc.set_critical(true);
             return;
           }
         }
       },
       "critical flag 1 contradicts singular"},
      {"arc singular mark removed",
       [](v1::TMesh& t) {
         // A singular arc claimed regular (and so not critical): the blocks around it decide.
         for (int a = 0; a < t.arcs_size(); ++a) {
           v1::Arc& arc = *t.mutable_arcs(a);
           if (arc.singular() != 0 && !arc.feature()) {
             arc.set_singular(0);
             arc.set_critical(false);
             return;
           }
         }
       },
       "singular mark 0 contradicts the"},
      {"arc singular mark invented",
       [](v1::TMesh& t) {
         for (int a = 0; a < t.arcs_size(); ++a) {
           v1::Arc& arc = *t.mutable_arcs(a);
           if (arc.singular() == 0) {
             arc.set_singular(1);
             arc.set_critical(true);
             return;
           }
         }
       },
       "singular mark 1 contradicts the"},
      {"arc boundary flag",
       [](v1::TMesh& t) {
         for (int a = 0; a < t.arcs_size(); ++a) {
           if (!t.arcs(a).boundary()) {
             t.mutable_arcs(a)->set_boundary(true);
             return;
           }
         }
       },
       "boundary flag 1 but it does not lie on a boundary patch"},
      {"arc feature without features present",
       [](v1::TMesh& t) {
         // The sample marks features; a file saying it has none may not mark any.
         t.mutable_features_present()->set_arcs(false);
       },
       "marked feature but featuresPresent.arcs is false"},
      {"critical entity missing", [](v1::TMesh& t) { t.mutable_critical_entities()->RemoveLast(); },
       "missing from the request (the mesh makes it region"},
      {"critical entity extra",
       [](v1::TMesh& t) {
         v1::CriticalEntity extra = t.critical_entities(0);
         extra.set_id(t.critical_entities_size());
         *t.add_critical_entities() = extra;
       },
       "critical entities, the request lists"},
      {"critical node entity dropped",
       [](v1::TMesh& t) {
         // The list without its first node entity, renumbered: every later entity shifts.
         t.mutable_critical_entities()->DeleteSubrange(0, 1);
         for (int e = 0; e < t.critical_entities_size(); ++e) {
           t.mutable_critical_entities(e)->set_id(e);
         }
       },
       "critical entity 0: the mesh makes it node"},
      {"arc halfpatch huge id",
       [](v1::TMesh& t) { t.mutable_arcs(2)->set_halfpatches(0, kHugeId); },
       "arc 2: halfpatch 2147483647 does not exist"},
      {"arc halfpatches wrong",
       [](v1::TMesh& t) {
         auto* hps = t.mutable_arcs(2)->mutable_halfpatches();
         hps->Set(0, hps->Get(0) ^ 1);
       },
       "arc 2: halfpatches"},
      {"node position truncated",
       [](v1::TMesh& t) { t.mutable_nodes(1)->mutable_position()->RemoveLast(); },
       "node 1: position has 2 coordinates"},
      {"node outgoing huge id",
       [](v1::TMesh& t) { t.mutable_nodes(0)->set_outgoing_halfarcs(0, kHugeId); },
       "node 0: outgoing halfarc 2147483647 does not exist"},
      {"node outgoing missing",
       [](v1::TMesh& t) { t.mutable_nodes(0)->mutable_outgoing_halfarcs()->RemoveLast(); },
       "is missing"},
      {"node outgoing wrong tail",
       [](v1::TMesh& t) {
         auto* out = t.mutable_nodes(0)->mutable_outgoing_halfarcs();
         out->Set(0, out->Get(0) ^ 1);
       },
       "node 0: outgoing halfarc"},
      {"node critical flag",
       [](v1::TMesh& t) { t.mutable_nodes(0)->set_critical(!t.nodes(0).critical()); },
       "node 0: critical flag"},
      {"node singular type",
       [singular_node](v1::TMesh& t) {
         t.mutable_nodes(singular_node)->set_singular_type(v1::SingularType::SEMI_SINGULAR);
       },
       "node " + std::to_string(singular_node) + ": singularType SEMI_SINGULAR but"},
      {"node feature type",
       [semi_feature_node](v1::TMesh& t) {
         t.mutable_nodes(semi_feature_node)->set_feature_type(v1::FeatureType::REGULAR);
       },
       "node " + std::to_string(semi_feature_node) +
           ": featureType REGULAR but its marks make it SEMI_FEATURE"},
      {"patch block huge id", [](v1::TMesh& t) { t.mutable_patches(0)->set_blocks(0, kHugeId); },
       "patch 0: block 2147483647 does not exist"},
      {"patch self adjacent",
       [interior](v1::TMesh& t) {
         t.mutable_patches(interior)->set_blocks(1, t.patches(interior).blocks(0));
       },
       interior_name + " block"},
      {"patch cycle not closed",
       [](v1::TMesh& t) {
         auto* cycle = t.mutable_patches(1)->mutable_halfarcs();
         cycle->SwapElements(0, 1);
       },
       "patch 1: cycle is not closed"},
      {"halfpatch faces away from its block",
       [](v1::TMesh& t) {
         // Boundary patch 0 moved to its other side: every list still agrees, but the cycle of
         // the halfpatch now facing the block winds about the outward normal.
         v1::Patch& patch = *t.mutable_patches(0);
         const int32_t b = patch.blocks(0);
         patch.set_blocks(0, -1);
         patch.set_blocks(1, b);
         patch.set_sides(1, patch.sides(0));
         patch.set_sides(0, v1::NONE);
         for (int32_t& hp : *t.mutable_blocks(b)->mutable_halfpatches()) {
           if (hp == 0) hp = 1;
         }
       },
       "patch 0: the cycle of halfpatch 1 turns about"},
      {"patch halfarc huge id",
       [](v1::TMesh& t) { t.mutable_patches(1)->set_halfarcs(0, kHugeId); },
       "patch 1: halfarc 2147483647 does not exist"},
      {"patch side direction",
       [](v1::TMesh& t) {
         auto* sides = t.mutable_patches(2)->mutable_halfarcs_by_dir();
         const v1::UVWDir first = sides->Get(0).dir();
         sides->Mutable(0)->set_dir(sides->Get(1).dir());
         sides->Mutable(1)->set_dir(first);
       },
       "patch 2:"},
      {"patch three sides",
       [](v1::TMesh& t) { t.mutable_patches(3)->mutable_halfarcs_by_dir()->RemoveLast(); },
       "patch 3: has 3 sides, not 4"},
      {"patch sides unequal",
       [](v1::TMesh& t) {
         // Lengthen one side's first arc everywhere it is used: the patch sides now differ.
         v1::DirectedHalfarcs* side =
             SideOf(t.mutable_patches(0), t.patches(0).halfarcs_by_dir(0).dir());
         const int arc = side->halfarcs(0) >> 1;
         t.mutable_arcs(arc)->set_length(t.arcs(arc).length() * 1.5);
       },
       "has continuous length"},
      {"transition not a permutation",
       [rotated](v1::TMesh& t) {
         t.mutable_patches(rotated)->mutable_transition()->set_rotation(
             1, t.patches(rotated).transition().rotation(0));
       },
       rotated_name + " transition rotation"},
      {"transition improper",
       [interior](v1::TMesh& t) {
         auto* r = t.mutable_patches(interior)->mutable_transition()->mutable_rotation();
         r->Set(0, -r->Get(0));
       },
       interior_name + " transition rotation"},
      {"transition inconsistent with frames",
       [interior](v1::TMesh& t) {
         auto* r = t.mutable_patches(interior)->mutable_transition()->mutable_rotation();
         r->Set(0, -1);
         r->Set(1, -2);
         r->Set(2, 3);
       },
       interior_name + " transition does not map"},
      {"boundary transition",
       [](v1::TMesh& t) {
         for (int p = 0; p < t.patches_size(); ++p) {
           if (t.patches(p).blocks(1) == -1) {
             auto* r = t.mutable_patches(p)->mutable_transition()->mutable_rotation();
             r->Set(0, 2);
             r->Set(1, -1);
             return;
           }
         }
       },
       "boundary patch with a non-identity transition"},
      {"transition translation NaN",
       [](v1::TMesh& t) {
         t.mutable_patches(0)->mutable_transition()->set_translation(0, std::nan(""));
       },
       "patch 0: transition translation is not finite"},
      {"transition translation shifted",
       [rotated](v1::TMesh& t) {
         auto* translation =
             t.mutable_patches(rotated)->mutable_transition()->mutable_translation();
         translation->Set(0, translation->Get(0) + 0.5);
       },
       rotated_name + " transition translation ["},
      {"transition translation zero where it is not",
       [rotated](v1::TMesh& t) {
         auto* translation =
             t.mutable_patches(rotated)->mutable_transition()->mutable_translation();
         for (int i = 0; i < 3; ++i) translation->Set(i, 0);
       },
       rotated_name + " transition translation [0,0,0] does not carry node"},
      {"block seven corners",
       [](v1::TMesh& t) { t.mutable_blocks(0)->mutable_corners()->RemoveLast(); },
       "block 0: has 7 corners, not 8"},
      {"block duplicate corner",
       [](v1::TMesh& t) {
         t.mutable_blocks(1)->mutable_corners(1)->set_corner(t.blocks(1).corners(0).corner());
       },
       "block 1: corner"},
      {"block corner is an edge key",
       [](v1::TMesh& t) { t.mutable_blocks(1)->mutable_corners(0)->set_corner(v1::POS_U_POS_V); },
       "block 1: corner key POS_U_POS_V is not a corner"},
      {"block eleven edges",
       [](v1::TMesh& t) { t.mutable_blocks(0)->mutable_edges()->RemoveLast(); },
       "block 0: has 11 edges, not 12"},
      {"block edge reversed",
       [](v1::TMesh& t) {
         auto* e = t.mutable_blocks(0)->mutable_edges(0);
         e->set_halfarcs(0, e->halfarcs(0) ^ 1);
       },
       "block 0: edge"},
      {"block five faces", [](v1::TMesh& t) { t.mutable_blocks(2)->mutable_faces()->RemoveLast(); },
       "block 2: has 5 faces, not 6"},
      {"block face lists foreign patch",
       [](v1::TMesh& t) {
         auto* face = t.mutable_blocks(0)->mutable_faces(0);
         face->set_patches(0, t.blocks(0).faces(1).patches(0));
       },
       "block 0: face"},
      {"block duplicate arc",
       [](v1::TMesh& t) {
         auto* by_dir = t.mutable_blocks(0)->mutable_arcs_by_dir();
         by_dir->Mutable(1)->add_arcs(by_dir->Get(0).arcs(0));
       },
       "block 0: arc"},
      {"block halfpatch missing",
       [](v1::TMesh& t) { t.mutable_blocks(0)->mutable_halfpatches()->RemoveLast(); },
       "but the block does not list halfpatch"},
      {"block halfpatch foreign",
       [](v1::TMesh& t) { t.mutable_blocks(0)->set_halfpatches(0, t.blocks(1).halfpatches(0)); },
       "block 0: lists halfpatch"},
      {"block coordinates shifted",
       [](v1::TMesh& t) {
         auto* uvw = t.mutable_blocks(0)->mutable_node_uvw(0)->mutable_uvw();
         uvw->Set(0, uvw->Get(0) + 0.25);
       },
       "block 0: arc"},
      {"block self adjacent flag",
       [](v1::TMesh& t) { t.mutable_blocks(3)->set_self_adjacent(true); },
       "block 3: self-adjacent blocks are not supported"},
      {"entity dim", [](v1::TMesh& t) { t.mutable_critical_entities(0)->set_dim(5); },
       "critical entity 0: dim 5"},
      {"entity id", [](v1::TMesh& t) { t.mutable_critical_entities(2)->set_id(7); },
       "critical entity 2: id is 7"},
      {"link broken",
       [](v1::TMesh& t) {
         for (auto& e : *t.mutable_critical_entities()) {
           if (e.dim() == 1) {
             e.set_halfarcs(0, e.halfarcs(0) ^ 1);
             return;
           }
         }
       },
       "the request says link"},
      {"region of non-critical patch",
       [](v1::TMesh& t) {
         int non_critical = -1;
         for (int p = 0; p < t.patches_size(); ++p) {
           if (!t.patches(p).critical()) non_critical = p;
         }
         for (auto& e : *t.mutable_critical_entities()) {
           if (e.dim() == 2) {
             e.set_patches(0, non_critical);
             return;
           }
         }
       },
       "the request says region"},
      {"level percent", [](v1::TMesh& t) { t.mutable_levels(2)->set_percent(3); },
       "level 2: percent 3"},
      {"level scaling", [](v1::TMesh& t) { t.mutable_levels(4)->set_scaling(1.0); },
       "level 4: scaling 1"},
  };
}

class CorruptionTest : public ::testing::TestWithParam<Corruption> {};

TEST_P(CorruptionTest, IsRejectedNamingTheElement) {
  v1::TMesh mesh = Tetrahedron();
  GetParam().mutate(mesh);
  const absl::StatusOr<TMesh> result = TMeshFromProto(mesh);
  ASSERT_FALSE(result.ok()) << GetParam().name << " was accepted";
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(result.status().message()), HasSubstr(GetParam().expected));
  // Decoded from its bytes one element at a time (core/proto/tmesh_from_wire.h): the same answer.
  const std::string bytes = mesh.SerializeAsString();
  const absl::StatusOr<TMesh> from_wire = TMeshFromWire([&bytes] {
    return std::make_unique<google::protobuf::io::ArrayInputStream>(bytes.data(),
                                                                    static_cast<int>(bytes.size()));
  });
  EXPECT_EQ(from_wire.status(), result.status());
}

INSTANTIATE_TEST_SUITE_P(RealFile, CorruptionTest, ::testing::ValuesIn(Corruptions()),
                         [](const ::testing::TestParamInfo<Corruption>& info) {
                           std::string name;
                           for (char c : info.param.name) name += std::isalnum(c) ? c : '_';
                           return name;
                         });

TEST(CorruptionTest, TableIsLargeAndAllKindsDiffer) {
  // The table must cover at least 25 distinct corruptions (the foundation issue's acceptance).
  std::set<std::string> names;
  for (const Corruption& c : Corruptions()) names.insert(c.name);
  EXPECT_GE(names.size(), 25u);
  EXPECT_EQ(names.size(), Corruptions().size());
}

// Critical entities are derived from the mesh, never taken from the request (issue 7): a mesh
// without its list gets exactly the file's entities, on every real mesh.
TEST(TMeshFromProtoTest, CriticalEntitiesAreDerivedWhenTheListIsLeftOut) {
  const std::vector<std::string> files = testing::RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (const std::string& file : files) {
    v1::TMesh proto = testing::LoadProtoOrDie(file);
    const TMesh listed = testing::TMeshOrDie(proto);
    proto.clear_critical_entities();
    const absl::StatusOr<TMesh> derived = TMeshFromProto(proto);
    ASSERT_TRUE(derived.ok()) << file << ": " << derived.status();
    ASSERT_EQ(derived->num_entities(), listed.num_entities()) << file;
    ASSERT_GT(derived->num_entities(), 0) << file;
    for (EntityId e = 0; e < listed.num_entities(); ++e) {
      EXPECT_EQ(derived->entity_dim(e), listed.entity_dim(e)) << file << " " << e;
      EXPECT_EQ(derived->entity_node_from(e), listed.entity_node_from(e)) << file << " " << e;
      EXPECT_EQ(derived->entity_node_to(e), listed.entity_node_to(e)) << file << " " << e;
      EXPECT_THAT(derived->entity_halfarcs(e),
                  ::testing::ElementsAreArray(listed.entity_halfarcs(e)));
      EXPECT_THAT(derived->entity_patches(e),
                  ::testing::ElementsAreArray(listed.entity_patches(e)));
    }
  }
}

// Translations may be omitted (proto/README.md, section Transitions): every real mesh loads
// without them, with the same arcs and critical entities, as the benchmark's compact files do.
TEST(TMeshFromProtoTest, OmittedTranslationsAreNotChecked) {
  for (const std::string& file : testing::RealTMeshFiles()) {
    v1::TMesh proto = testing::LoadProtoOrDie(file);
    const TMesh full = testing::TMeshOrDie(proto);
    for (v1::Patch& patch : *proto.mutable_patches()) {
      patch.mutable_transition()->clear_translation();
    }
    const absl::StatusOr<TMesh> compact = TMeshFromProto(proto);
    ASSERT_TRUE(compact.ok()) << file << ": " << compact.status();
    EXPECT_EQ(compact->num_arcs(), full.num_arcs()) << file;
    EXPECT_EQ(compact->num_entities(), full.num_entities()) << file;
  }
}

TEST(TMeshFromProtoTest, UncorruptedSampleIsAccepted) {
  const absl::StatusOr<TMesh> mesh = TMeshFromProto(Tetrahedron());
  ASSERT_TRUE(mesh.ok()) << mesh.status();
  EXPECT_EQ(mesh->num_arcs(), Tetrahedron().arcs_size());
}

}  // namespace
}  // namespace ispq
