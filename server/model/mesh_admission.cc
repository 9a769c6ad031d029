// SPDX-License-Identifier: Apache-2.0
#include "server/model/mesh_admission.h"

#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/proto/tmesh_from_wire.h"

namespace ispq::server {
namespace {

// The mesh and the reservation for its memory, owned together.
struct MeshWithMemory {
  TMesh mesh;
  MemoryReservation memory;
};

AdmittedMesh MakeAdmittedMesh(TMesh mesh, MemoryReservation memory) {
  AdmittedMesh admitted;
  admitted.stats = MeshStatsToProto(ComputeMeshStats(mesh));
  auto owner = std::make_shared<MeshWithMemory>(MeshWithMemory{std::move(mesh), std::move(memory)});
  admitted.mesh = std::shared_ptr<const TMesh>(owner, &owner->mesh);
  return admitted;
}

}  // namespace

absl::Status CheckMeshSize(const v1::TMesh& proto, int max_arcs) {
  return CheckArcCount(proto.arcs_size(), max_arcs);
}

absl::Status CheckArcCount(int64_t arcs, int max_arcs) {
  if (arcs <= max_arcs) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat(
      "mesh has ", arcs, " arcs; this server accepts at most ", max_arcs, " (--max_arcs)"));
}

absl::StatusOr<AdmittedMesh> AdmitMesh(const v1::TMesh& proto, int max_arcs,
                                       MemoryReservation memory) {
  if (absl::Status size = CheckMeshSize(proto, max_arcs); !size.ok()) return size;
  absl::StatusOr<TMesh> mesh = TMeshFromProto(proto);
  if (!mesh.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("invalid T-mesh: ", std::string(mesh.status().message())));
  }
  return MakeAdmittedMesh(*std::move(mesh), std::move(memory));
}

absl::StatusOr<AdmittedMesh> AdmitMeshBytes(const TMeshBytesReader& read, int max_arcs,
                                            MemoryReservation memory) {
  absl::Status size = absl::OkStatus();  // the size limit's answer, passed on as it is
  absl::StatusOr<TMesh> mesh = TMeshFromWire(read, [&](const TMeshWireCounts& counts) {
    size = CheckArcCount(counts.arcs, max_arcs);
    return size;
  });
  if (!size.ok()) return size;
  if (!mesh.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("invalid T-mesh: ", std::string(mesh.status().message())));
  }
  return MakeAdmittedMesh(*std::move(mesh), std::move(memory));
}

}  // namespace ispq::server
