// SPDX-License-Identifier: Apache-2.0
// The node positions of an admitted mesh (server/model/mesh_admission.h), for drawing it: the web
// view's geometry (server/http/mesh_geometry.h). The core model does not keep positions, since no
// algorithm reads them (core/tmesh_input.h); admission keeps them, in single precision, in the
// mesh's shared ownership beside its memory reservation, so that they live exactly as long as the
// mesh, are covered by its reservation (the estimate of server/memory/memory_estimates.h counts
// the wire bytes, which hold them in double precision) and need no change to the model.
#ifndef ISPQ_SERVER_MODEL_MESH_POSITIONS_H_
#define ISPQ_SERVER_MODEL_MESH_POSITIONS_H_

#include <array>
#include <memory>
#include <vector>

#include "core/tmesh.h"

namespace ispq::server {

// [x, y, z] per node, in node id order.
using NodePositions = std::vector<std::array<float, 3>>;

// The positions of `mesh`'s nodes if AdmitMesh made it, else null (a mesh built another way, as
// tests do). Valid as long as `mesh` is.
const NodePositions* NodePositionsOf(const std::shared_ptr<const TMesh>& mesh);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MODEL_MESH_POSITIONS_H_
