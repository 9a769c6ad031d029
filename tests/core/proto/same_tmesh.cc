// SPDX-License-Identifier: Apache-2.0
#include "tests/core/proto/same_tmesh.h"

#include "core/mesh_stats.h"
#include "gtest/gtest.h"

namespace ispq::testing {

void ExpectSameTMesh(const TMesh& a, const TMesh& b) {
  const MeshStats x = ComputeMeshStats(a), y = ComputeMeshStats(b);
  EXPECT_EQ(x.nodes, y.nodes);
  EXPECT_EQ(x.arcs, y.arcs);
  EXPECT_EQ(x.patches, y.patches);
  EXPECT_EQ(x.blocks, y.blocks);
  EXPECT_EQ(x.critical_entities, y.critical_entities);
  EXPECT_EQ(x.critical_links, y.critical_links);
  EXPECT_EQ(x.bundles, y.bundles);
  EXPECT_EQ(x.subproblems, y.subproblems);
  EXPECT_EQ(a.name(), b.name());
  ASSERT_EQ(a.num_arcs(), b.num_arcs());
  for (ArcId e = 0; e < a.num_arcs(); ++e) {
    ASSERT_EQ(a.arc_from(e), b.arc_from(e)) << "arc " << e;
    ASSERT_EQ(a.arc_length(e), b.arc_length(e)) << "arc " << e;
    ASSERT_EQ(a.arc_critical(e), b.arc_critical(e)) << "arc " << e;
  }
  ASSERT_EQ(a.levels().size(), b.levels().size());
}

}  // namespace ispq::testing
