#include "server/mesh_admission.h"

#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "core/proto/tmesh_from_proto.h"

namespace ispq::server {

absl::StatusOr<AdmittedMesh> AdmitMesh(const v1::TMesh& proto, int max_arcs) {
  if (proto.arcs_size() > max_arcs) {
    return absl::InvalidArgumentError(absl::StrCat("mesh has ", proto.arcs_size(),
                                                   " arcs; this server accepts at most ", max_arcs,
                                                   " (--max_arcs)"));
  }
  absl::StatusOr<TMesh> mesh = TMeshFromProto(proto);
  if (!mesh.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("invalid T-mesh: ", std::string(mesh.status().message())));
  }
  AdmittedMesh admitted;
  admitted.stats = MeshStatsToProto(ComputeMeshStats(*mesh));
  admitted.mesh = std::make_shared<const TMesh>(*std::move(mesh));
  return admitted;
}

}  // namespace ispq::server
