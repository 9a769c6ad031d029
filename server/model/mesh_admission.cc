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
#include "core/proto/tmesh_from_wire.h"
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

// A node's position (3 finite numbers: the decoder checked them before the mesh is admitted) in
// single precision, clamped so that a finite double beyond float's range is no undefined
// conversion.
std::array<float, 3> PositionOf(const v1::Node& node) {
  constexpr double kMax = std::numeric_limits<float>::max();
  std::array<float, 3> position = {};
  for (int i = 0; i < 3 && i < node.position_size(); ++i) {
    position[i] = static_cast<float>(std::clamp(node.position(i), -kMax, kMax));
  }
  return position;
}

NodePositions PositionsOf(const v1::TMesh& proto) {
  NodePositions positions;
  positions.reserve(proto.nodes_size());
  for (const v1::Node& node : proto.nodes()) positions.push_back(PositionOf(node));
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
  return MakeAdmittedMesh(*std::move(mesh), PositionsOf(proto), std::move(memory));
}

const NodePositions* NodePositionsOf(const std::shared_ptr<const TMesh>& mesh) {
  const MeshOwner* owner = std::get_deleter<MeshOwner>(mesh);
  return owner == nullptr ? nullptr : &owner->owner->positions;
}

absl::StatusOr<AdmittedMesh> AdmitMeshBytes(const TMeshBytesReader& read, int max_arcs,
                                            MemoryReservation memory) {
  absl::Status size = absl::OkStatus();  // the size limit's answer, passed on as it is
  NodePositions positions;
  TMeshWireHooks hooks;
  hooks.check_counts = [&](const TMeshWireCounts& counts) {
    size = CheckArcCount(counts.arcs, max_arcs);
    if (size.ok()) positions.reserve(counts.nodes);
    return size;
  };
  hooks.on_node = [&positions](const v1::Node& node) { positions.push_back(PositionOf(node)); };
  absl::StatusOr<TMesh> mesh = TMeshFromWire(read, hooks);
  if (!size.ok()) return size;
  if (!mesh.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("invalid T-mesh: ", std::string(mesh.status().message())));
  }
  return MakeAdmittedMesh(*std::move(mesh), std::move(positions), std::move(memory));
}

}  // namespace ispq::server
