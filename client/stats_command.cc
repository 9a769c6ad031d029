// SPDX-License-Identifier: Apache-2.0
#include "client/stats_command.h"

#include <iostream>

#include "client/exit_codes.h"
#include "client/mesh_file_input.h"
#include "client/message_json.h"
#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"

namespace ispq::cli {

int RunStatsCommand(const std::string& path, bool json) {
  const absl::StatusOr<TMesh> loaded = LoadMeshModel(path);
  if (!loaded.ok()) {
    std::cerr << "ispq: " << loaded.status().message() << "\n";
    return kExitInvalidInput;
  }
  const TMesh& mesh = *loaded;
  const MeshStats stats = ComputeMeshStats(mesh);
  if (json) {
    std::cout << MessageToJson(MeshStatsToProto(stats)) << "\n";
    return kExitOk;
  }
  std::cout << path << " (" << mesh.name() << ")\n"
            << "  blocks            " << stats.blocks << "\n"
            << "  patches           " << stats.patches << "\n"
            << "  arcs              " << stats.arcs << "\n"
            << "  nodes             " << stats.nodes << "\n"
            << "  critical          " << stats.critical_nodes << " nodes, " << stats.critical_arcs
            << " arcs, " << stats.critical_patches << " patches\n"
            << "  critical entities " << stats.critical_entities << " (" << stats.critical_links
            << " links, " << stats.critical_regions << " regions)\n"
            << "  consistency rows  " << stats.consistency_rows << " ("
            << stats.reduced_consistency_rows << " after bundling)\n"
            << "  bundles           " << stats.bundles << "\n"
            << "  subproblems       " << stats.subproblems << "\n";
  return kExitOk;
}

}  // namespace ispq::cli
