// SPDX-License-Identifier: Apache-2.0
// Counts that describe a T-mesh and the size of its quantization problem, as reported by
// `ispq stats` and in every job's "accepted" event.
#ifndef ISPQ_CORE_MESH_STATS_H_
#define ISPQ_CORE_MESH_STATS_H_

#include <cstdint>

#include "core/tmesh.h"

namespace ispq {

struct MeshStats {
  int32_t blocks = 0;
  int32_t patches = 0;
  int32_t arcs = 0;
  int32_t nodes = 0;
  int32_t critical_nodes = 0;
  int32_t critical_arcs = 0;
  int32_t critical_patches = 0;
  int32_t critical_entities = 0;
  int32_t critical_links = 0;
  int32_t critical_regions = 0;
  int32_t consistency_rows = 0;          // rows of A, two per patch
  int32_t reduced_consistency_rows = 0;  // rows left after merging bundles (non-trivial ones)
  int32_t bundles = 0;
  int32_t subproblems = 0;
};

MeshStats ComputeMeshStats(const TMesh& mesh);

}  // namespace ispq

#endif  // ISPQ_CORE_MESH_STATS_H_
