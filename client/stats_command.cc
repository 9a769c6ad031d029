#include "client/stats_command.h"

#include <iostream>

#include "client/exit_codes.h"
#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "google/protobuf/util/json_util.h"

namespace ispq::cli {

int RunStatsCommand(const std::string& path, bool json) {
  absl::StatusOr<v1::TMesh> proto = ReadTMeshFile(path);
  if (!proto.ok()) {
    std::cerr << "ispq: " << proto.status().message() << "\n";
    return kExitInvalidInput;
  }
  absl::StatusOr<TMesh> mesh = TMeshFromProto(*proto);
  if (!mesh.ok()) {
    std::cerr << "ispq: " << path << ": " << mesh.status().message() << "\n";
    return kExitInvalidInput;
  }
  const MeshStats stats = ComputeMeshStats(*mesh);
  if (json) {
    std::string out;
    google::protobuf::util::JsonPrintOptions options;
    options.always_print_primitive_fields = true;
    (void)google::protobuf::util::MessageToJsonString(MeshStatsToProto(stats), &out, options);
    std::cout << out << "\n";
    return kExitOk;
  }
  std::cout << path << " (" << mesh->name() << ")\n"
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
