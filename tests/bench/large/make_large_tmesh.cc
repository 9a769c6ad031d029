// SPDX-License-Identifier: Apache-2.0
// Writes one large synthetic T-mesh (large_tmesh_generator.h) as binary protobuf or JSON:
//
//   ispq_make_large_tmesh --family single|slabs|rotated --arcs N [--seed S] --out F.tmesh.pb
#include <fstream>
#include <iostream>
#include <string>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/strings/match.h"
#include "tests/bench/large/large_tmesh_generator.h"

ABSL_FLAG(std::string, family, "single", "single, slabs or rotated");
ABSL_FLAG(int, arcs, 10000, "about this many arcs");
ABSL_FLAG(uint64_t, seed, 1, "random seed");
ABSL_FLAG(std::string, out, "", "output file (.pb: binary, otherwise JSON)");

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  const auto family = ispq::bench::LargeFamilyFromName(absl::GetFlag(FLAGS_family));
  if (!family.has_value() || absl::GetFlag(FLAGS_out).empty()) {
    std::cerr << "usage: ispq_make_large_tmesh --family single|slabs|rotated --arcs N --out F\n";
    return 2;
  }
  absl::StatusOr<ispq::testing::GridTMesh> mesh =
      ispq::bench::BuildLargeTMesh(*family, absl::GetFlag(FLAGS_arcs), absl::GetFlag(FLAGS_seed));
  if (!mesh.ok()) {
    std::cerr << mesh.status() << "\n";
    return 1;
  }
  const std::string path = absl::GetFlag(FLAGS_out);
  std::string bytes;
  if (absl::EndsWith(path, ".pb")) {
    bytes = mesh->proto().SerializeAsString();
  } else {
    absl::StatusOr<std::string> json = ispq::testing::TMeshToJson(mesh->proto());
    if (!json.ok()) {
      std::cerr << json.status() << "\n";
      return 1;
    }
    bytes = *json;
  }
  std::ofstream(path, std::ios::binary) << bytes;
  std::cout << path << ": " << mesh->proto().arcs_size() << " arcs, " << mesh->proto().blocks_size()
            << " blocks\n";
  return 0;
}
