// SPDX-License-Identifier: Apache-2.0
#include "server/model/mesh_admission.h"

#include <algorithm>
#include <limits>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "core/proto/tmesh_from_proto.h"
#include "server/model/mesh_positions.h"

namespace ispq::server {
namespace {

// The mesh, its node positions and the reservation for its memory, owned together.
struct MeshWithMemory {
  TMesh mesh;
  NodePositions positions;
  MemoryReservation memory;
};

// The deleter of an admitted mesh's shared pointer: it owns the whole, so that NodePositionsOf can
// find the positions from the pointer alone (std::get_deleter), with no field in the model.
struct MeshOwner {
  std::shared_ptr<const MeshWithMemory> owner;
  void operator()(const TMesh*) const {}
};

// The proto's positions (3 finite numbers each: TMeshFromProto checked them) in single
// precision, clamped so that a finite double beyond float's range is no undefined conversion.
NodePositions PositionsOf(const v1::TMesh& proto) {
  constexpr double kMax = std::numeric_limits<float>::max();
  NodePositions positions(proto.nodes_size());
  for (int n = 0; n < proto.nodes_size(); ++n) {
    const auto& position = proto.nodes(n).position();
    for (int i = 0; i < 3 && i < position.size(); ++i) {
      positions[n][i] = static_cast<float>(std::clamp(position[i], -kMax, kMax));
    }
  }
  return positions;
}

AdmittedMesh MakeAdmittedMesh(TMesh mesh, NodePositions positions, MemoryReservation memory) {
  AdmittedMesh admitted;
  admitted.stats = MeshStatsToProto(ComputeMeshStats(mesh));
  auto owner = std::make_shared<MeshWithMemory>(
      MeshWithMemory{std::move(mesh), std::move(positions), std::move(memory)});
  const TMesh* model = &owner->mesh;
  admitted.mesh = std::shared_ptr<const TMesh>(model, MeshOwner{std::move(owner)});
  return admitted;
}

}  // namespace

absl::Status CheckMeshSize(const v1::TMesh& proto, int max_arcs) {
  if (proto.arcs_size() <= max_arcs) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat("mesh has ", proto.arcs_size(),
                                                 " arcs; this server accepts at most ", max_arcs,
                                                 " (--max_arcs)"));
}

absl::StatusOr<AdmittedMesh> AdmitMesh(const v1::TMesh& proto, int max_arcs,
                                       MemoryReservation memory) {
  if (absl::Status size = CheckMeshSize(proto, max_arcs); !size.ok()) return size;
  absl::StatusOr<TMesh> mesh = TMeshFromProto(proto);
  if (!mesh.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("invalid T-mesh: ", std::string(mesh.status().message())));
  }
  return MakeAdmittedMesh(*std::move(mesh), PositionsOf(proto), std::move(memory));
}

const NodePositions* NodePositionsOf(const std::shared_ptr<const TMesh>& mesh) {
  const MeshOwner* owner = std::get_deleter<MeshOwner>(mesh);
  return owner == nullptr ? nullptr : &owner->owner->positions;
}

}  // namespace ispq::server
