// SPDX-License-Identifier: Apache-2.0
// Writes one large synthetic T-mesh (large_tmesh_generator.h) as binary protobuf or JSON:
//
//   ispq_make_large_tmesh --family single|slabs|rotated|assembly16|assembly50|assembly100
//                         --arcs N [--seed S] [--compact] --out F.tmesh.pb
//
// --compact leaves out what the format makes optional and ispq derives or ignores: the critical
// entities (the loader derives them; given, it only compares) and the transitions' translations
// (never read). The loader refuses files over 256 MiB (core/proto/tmesh_file.h), and a 10^6-arc
// assembly100 mesh is 296 MB in full: entities 32 MB, translations 18 MB (node coordinates in
// blocks, 63 MB, are required). The loaded mesh is the same either way.
//
// For the assembly families, the density knobs of assembly_tmesh_generator.h can be overridden
// one by one (--part_min, --part_max, --block_max, --feature_share, --voids_per_part,
// --edge_share), to explore densities beside the presets; the mesh is then named after the family
// with a "-custom" suffix.
#include <fstream>
#include <iostream>
#include <optional>
#include <string>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/strings/match.h"
#include "tests/bench/large/large_tmesh_generator.h"

ABSL_FLAG(std::string, family, "single",
          "single, slabs, rotated, assembly16, assembly50 or assembly100");
ABSL_FLAG(int, arcs, 10000, "about this many arcs");
ABSL_FLAG(uint64_t, seed, 1, "random seed");
ABSL_FLAG(std::string, out, "", "output file (.pb: binary, otherwise JSON)");
ABSL_FLAG(bool, compact, false,
          "leave out the optional critical entities and transition translations");
ABSL_FLAG(int, part_min, -1, "assembly families: smallest part, cells per axis");
ABSL_FLAG(int, part_max, -1, "assembly families: largest part, cells per axis");
ABSL_FLAG(int, block_max, -1, "assembly families: largest block, cells per axis");
ABSL_FLAG(double, feature_share, -1, "assembly families: share of feature interfaces");
ABSL_FLAG(double, voids_per_part, -1, "assembly families: mean voids per part");
ABSL_FLAG(double, edge_share, -1, "assembly families: share of part edges that are features");

namespace {

// The family's preset with the overrides given on the command line; whether any was given.
bool Override(ispq::bench::AssemblyDensity& d) {
  bool changed = false;
  auto take = [&changed](auto& field, auto value) {
    if (value < 0) return;
    field = value;
    changed = true;
  };
  take(d.part_min, absl::GetFlag(FLAGS_part_min));
  take(d.part_max, absl::GetFlag(FLAGS_part_max));
  take(d.block_max, absl::GetFlag(FLAGS_block_max));
  take(d.feature_share, absl::GetFlag(FLAGS_feature_share));
  take(d.voids_per_part, absl::GetFlag(FLAGS_voids_per_part));
  take(d.edge_share, absl::GetFlag(FLAGS_edge_share));
  return changed;
}

}  // namespace

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  const auto family = ispq::bench::LargeFamilyFromName(absl::GetFlag(FLAGS_family));
  if (!family.has_value() || absl::GetFlag(FLAGS_out).empty()) {
    std::cerr << "usage: ispq_make_large_tmesh --family "
                 "single|slabs|rotated|assembly16|assembly50|assembly100 --arcs N --out F\n";
    return 2;
  }
  const int arcs = absl::GetFlag(FLAGS_arcs);
  const uint64_t seed = absl::GetFlag(FLAGS_seed);
  absl::StatusOr<ispq::testing::GridTMesh> mesh;
  std::optional<ispq::bench::AssemblyDensity> density = ispq::bench::AssemblyDensityOf(*family);
  if (density.has_value() && Override(*density)) {
    density->name += "-custom";
    mesh = ispq::bench::BuildAssemblyTMesh(*density, arcs, seed);
  } else {
    mesh = ispq::bench::BuildLargeTMesh(*family, arcs, seed);
  }
  if (!mesh.ok()) {
    std::cerr << mesh.status() << "\n";
    return 1;
  }
  if (absl::GetFlag(FLAGS_compact)) {
    ispq::v1::TMesh& proto = *mesh->mutable_proto();
    proto.clear_critical_entities();
    for (ispq::v1::Patch& patch : *proto.mutable_patches()) {
      patch.mutable_transition()->clear_translation();
    }
  }
  const std::string path = absl::GetFlag(FLAGS_out);
  std::ofstream out(path, std::ios::binary);
  if (absl::EndsWith(path, ".pb")) {
    // Straight to the file: a 10^6-arc mesh's bytes need not sit in memory beside its message.
    mesh->proto().SerializeToOstream(&out);
  } else {
    absl::StatusOr<std::string> json = ispq::testing::TMeshToJson(mesh->proto());
    if (!json.ok()) {
      std::cerr << json.status() << "\n";
      return 1;
    }
    out << *json;
  }
  out.close();
  if (!out) {
    std::cerr << "cannot write " << path << "\n";
    return 1;
  }
  std::cout << path << ": " << mesh->proto().arcs_size() << " arcs, " << mesh->proto().blocks_size()
            << " blocks\n";
  return 0;
}
