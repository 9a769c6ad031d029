// SPDX-License-Identifier: Apache-2.0
// The door from a client's ispq.v1.TMesh into the server: the server's size limit first (before
// anything is built from the message), then the core validator (core/proto/tmesh_from_proto.h,
// or core/proto/tmesh_from_wire.h for an uploaded mesh that is never parsed as one message), then
// the mesh statistics every job reports in its accepted event.
//
// A rejected mesh is INVALID_ARGUMENT with the validator's message, which names the offending
// element, so that a client can fix its exporter.
//
// The admitted mesh carries the memory reservation made for it (server/memory/memory_budget.h) in
// its shared ownership: the bytes are released when the last job or store entry lets go of the
// mesh.
#ifndef ISPQ_SERVER_MODEL_MESH_ADMISSION_H_
#define ISPQ_SERVER_MODEL_MESH_ADMISSION_H_

#include <memory>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/proto/tmesh_from_wire.h"
#include "core/tmesh.h"
#include "ispq/v1/mesh_stats.pb.h"
#include "ispq/v1/tmesh.pb.h"
#include "server/memory/memory_budget.h"

namespace ispq::server {

// A validated mesh, immutable and shared by every job that runs on it.
struct AdmittedMesh {
  std::shared_ptr<const TMesh> mesh;
  v1::MeshStats stats;
};

// The size limit alone, for checking before memory is reserved for the mesh.
absl::Status CheckMeshSize(const v1::TMesh& proto, int max_arcs);

absl::StatusOr<AdmittedMesh> AdmitMesh(const v1::TMesh& proto, int max_arcs,
                                       MemoryReservation memory = MemoryReservation());

// The same from the mesh's serialized bytes, never held as one parsed message
// (core/proto/tmesh_from_wire.h): the arc count is checked before any element is decoded.
absl::Status CheckArcCount(int64_t arcs, int max_arcs);
absl::StatusOr<AdmittedMesh> AdmitMeshBytes(const TMeshBytesReader& read, int max_arcs,
                                            MemoryReservation memory = MemoryReservation());

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MODEL_MESH_ADMISSION_H_
