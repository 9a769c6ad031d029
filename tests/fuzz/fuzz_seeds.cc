// SPDX-License-Identifier: Apache-2.0
// Writes the seed corpora: for quantize_request_fuzzer one binary ispq.v1.QuantizeRequest per
// real T-mesh of at most kMaxArcsToQuantize arcs and scaling (levels 0, 50 and 100, a factor
// and a target hex count), into the first directory given; for tmesh_wire_fuzzer every real
// T-mesh as a binary ispq.v1.TMesh, into the second.
#include <fstream>
#include <iostream>
#include <string>

#include "ispq/v1/service.pb.h"
#include "tests/fuzz/bounded_quantize.h"
#include "tests/support/test_data.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: ispq_fuzz_seeds REQUEST_DIR TMESH_DIR\n";
    return 2;
  }
  int written = 0, meshes = 0;
  for (const std::string& file : ispq::testing::RealTMeshFiles()) {
    const ispq::v1::TMesh mesh = ispq::testing::LoadProtoOrDie(file);
    std::ofstream(std::string(argv[2]) + "/tmesh-" + std::to_string(meshes++), std::ios::binary)
        << mesh.SerializeAsString();
    if (mesh.arcs_size() > ispq::fuzz::kMaxArcsToQuantize) continue;
    for (int variant = 0; variant < 5; ++variant) {
      ispq::v1::QuantizeRequest request;
      *request.mutable_mesh() = mesh;
      ispq::v1::Scaling& scaling = *request.mutable_options()->mutable_scaling();
      if (variant < 3) scaling.set_level_percent(variant == 0 ? 0 : (variant == 1 ? 50 : 100));
      if (variant == 3) scaling.set_factor(2.5);
      if (variant == 4) scaling.set_target_hexes(1000);
      std::ofstream out(std::string(argv[1]) + "/seed-" + std::to_string(written++),
                        std::ios::binary);
      out << request.SerializeAsString();
    }
  }
  std::cout << written << " request seeds, " << meshes << " T-mesh seeds\n";
  return written > 0 ? 0 : 1;
}
