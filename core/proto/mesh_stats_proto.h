// SPDX-License-Identifier: Apache-2.0
// MeshStats as its ispq.v1 message, for the CLI's JSON output and the service's events.
#ifndef ISPQ_CORE_PROTO_MESH_STATS_PROTO_H_
#define ISPQ_CORE_PROTO_MESH_STATS_PROTO_H_

#include "core/mesh_stats.h"
#include "ispq/v1/mesh_stats.pb.h"

namespace ispq {

v1::MeshStats MeshStatsToProto(const MeshStats& stats);

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_MESH_STATS_PROTO_H_
