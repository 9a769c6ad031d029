// SPDX-License-Identifier: Apache-2.0
// The greedy descent's queue: roots furthest from their targets first, outdated entries skipped,
// and re-queuing exactly the roots whose last solve depended on what a sheet changed.
#include "core/isp/greedy_queue.h"

#include <algorithm>
#include <optional>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

// A single block of extents 3 x 2 x 1: three bundles (the u, v and w edges), whose distances
// to their targets at q = 0 are 3, 2 and 1.
class GreedyQueueTest : public ::testing::Test {
 protected:
  GreedyQueueTest()
      : mesh_(Cuboid()),
        consistency_(mesh_),
        bundles_(mesh_, consistency_),
        quantization_(mesh_, bundles_, 1.0),
        rows_(bundles_.num_bundles()),
        queue_(quantization_, rows_) {}

  static TMesh Cuboid() {
    testing::GridTMeshSpec spec;
    spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
    spec.spacing = {{{3.0}, {2.0}, {1.0}}};
    return testing::TMeshOrDie(testing::BuildGridTMesh(spec)->proto());
  }
  BundleId BundleAlong(int axis) const {
    return bundles_.bundle_of(mesh_.block_edge_arcs(0, EdgeCode(axis, false, false))[0]);
  }
  std::vector<BundleId> Drain() {
    std::vector<BundleId> popped;
    while (std::optional<BundleId> b = queue_.Pop()) popped.push_back(*b);
    return popped;
  }

  const TMesh mesh_;
  const ConsistencyMatrix consistency_;
  const ArcBundles bundles_;
  BundleQuantization quantization_;
  InequalityRows rows_;
  GreedyQueue queue_;
};

TEST_F(GreedyQueueTest, PopsTheRootsFurthestFromTheirTargetsFirst) {
  ASSERT_EQ(bundles_.num_bundles(), 3);
  queue_.Reset();
  EXPECT_EQ(Drain(), (std::vector<BundleId>{BundleAlong(0), BundleAlong(1), BundleAlong(2)}));
  // Reset queues every bundle again, each once.
  queue_.Reset();
  EXPECT_EQ(Drain().size(), 3u);
}

TEST_F(GreedyQueueTest, RequeuesTheRootsThatDependedOnAMovedBundle) {
  const BundleId u = BundleAlong(0), v = BundleAlong(1), w = BundleAlong(2);
  queue_.Reset();
  ASSERT_EQ(queue_.Pop(), u);
  queue_.RecordDependencies(u, std::vector<BundleId>{u, v});  // u's sheet went through v
  ASSERT_EQ(queue_.Pop(), v);
  queue_.RecordDependencies(v, std::vector<BundleId>{v});
  ASSERT_EQ(queue_.Pop(), w);
  queue_.RecordDependencies(w, std::vector<BundleId>{w});
  ASSERT_EQ(queue_.Pop(), std::nullopt);

  IntegerSheet sheet;
  sheet.bundles = {v};
  sheet.deltas = {1};
  queue_.RequeueAfter(sheet);  // v moved: u and v solve again, w does not
  EXPECT_EQ(Drain(), (std::vector<BundleId>{u, v}));
  // Dependencies are used once: a second change of v re-queues only v itself.
  queue_.RequeueAfter(sheet);
  EXPECT_EQ(Drain(), (std::vector<BundleId>{v}));
}

TEST_F(GreedyQueueTest, AnInfeasibleSolveDependsOnTheRowsAroundTheRoot) {
  const BundleId u = BundleAlong(0), v = BundleAlong(1), w = BundleAlong(2);
  const std::vector<LinearTerm> coupling = {{std::min(u, w), 1}, {std::max(u, w), 1}};
  rows_.Add(coupling, 1, RowOrigin::kStructural, /*active=*/true, quantization_.values());
  queue_.Reset();
  ASSERT_EQ(queue_.Pop(), u);
  queue_.RecordDependencies(u, {});  // no sheet: u waits for the slack of u + w >= 1
  ASSERT_EQ(queue_.Pop(), v);
  queue_.RecordDependencies(v, {});
  ASSERT_EQ(queue_.Pop(), w);
  queue_.RecordDependencies(w, {});

  IntegerSheet sheet;
  sheet.bundles = {w};
  sheet.deltas = {1};
  queue_.RequeueAfter(sheet);
  EXPECT_EQ(Drain(), (std::vector<BundleId>{u, w}));
}

TEST_F(GreedyQueueTest, ANewRowRequeuesOnlyTheRootsWhoseSheetCrossedIt) {
  const BundleId u = BundleAlong(0), v = BundleAlong(1), w = BundleAlong(2);
  EXPECT_FALSE(queue_.started());
  queue_.Reset();
  EXPECT_TRUE(queue_.started());
  ASSERT_EQ(queue_.Pop(), u);
  queue_.RecordDependencies(u, std::vector<BundleId>{u, v});
  ASSERT_EQ(queue_.Pop(), v);
  queue_.RecordDependencies(v, std::vector<BundleId>{v});
  ASSERT_EQ(queue_.Pop(), w);
  queue_.RecordDependencies(w, std::vector<BundleId>{w});
  ASSERT_EQ(queue_.Pop(), std::nullopt);

  // A row over u alone: only u's sheet crossed it (v's and w's left u alone).
  queue_.RequeueUsersOf(std::vector<BundleId>{u});
  EXPECT_EQ(Drain(), (std::vector<BundleId>{u}));
  // A row over v: u's old sheet crossed v too, but u's dependencies were used by the row above,
  // so only v is pumped again.
  queue_.RequeueUsersOf(std::vector<BundleId>{v});
  EXPECT_EQ(Drain(), (std::vector<BundleId>{v}));
}

TEST_F(GreedyQueueTest, RootsAPassDidNotReachStayQueuedForTheNextOne) {
  const BundleId u = BundleAlong(0), v = BundleAlong(1), w = BundleAlong(2);
  queue_.Reset();
  ASSERT_EQ(queue_.Pop(), u);  // a pass that stops after one root
  queue_.RecordDependencies(u, std::vector<BundleId>{u});
  // The next pass goes on with v and w instead of starting over.
  EXPECT_EQ(Drain(), (std::vector<BundleId>{v, w}));
}

// Roots answered by one covering sheet record it once, and all come back when it changes.
TEST_F(GreedyQueueTest, RootsAnsweredByTheSameSheetShareItsRecord) {
  const BundleId u = BundleAlong(0), v = BundleAlong(1), w = BundleAlong(2);
  queue_.Reset();
  Drain();
  const std::vector<BundleId> sheet_bundles = {std::min(u, v), std::max(u, v)};
  queue_.RecordDependencies(u, sheet_bundles, /*shared=*/7);
  queue_.RecordDependencies(w, sheet_bundles, /*shared=*/7);
  EXPECT_EQ(queue_.num_recorded_dependencies(), 2);
  IntegerSheet only_v;
  only_v.bundles = {v};
  only_v.deltas = {1};
  queue_.RequeueAfter(only_v);
  EXPECT_EQ(Drain(), (std::vector<BundleId>{u, v, w}));
  // The record is used up: another change of v re-queues v alone.
  queue_.RequeueAfter(only_v);
  EXPECT_EQ(Drain(), (std::vector<BundleId>{v}));
}

TEST_F(GreedyQueueTest, OutdatedDependenciesAreDroppedAndCurrentOnesKept) {
  const BundleId u = BundleAlong(0), v = BundleAlong(1), w = BundleAlong(2);
  queue_.Reset();
  Drain();
  queue_.RecordDependencies(w, std::vector<BundleId>{v, w});  // w's sheet went through v
  // u's sheet goes through v too, but u is queued again every time because u itself moves: each
  // time its record at v becomes outdated without v ever changing.
  IntegerSheet only_u;
  only_u.bundles = {u};
  only_u.deltas = {1};
  for (int i = 0; i < 1000; ++i) {
    queue_.RecordDependencies(u, std::vector<BundleId>{u, v});
    queue_.RequeueAfter(only_u);
    ASSERT_EQ(Drain(), (std::vector<BundleId>{u}));
  }
  EXPECT_LE(queue_.num_recorded_dependencies(), 32 * 3 + 2);
  // v moves: w's record survived the dropping; none of u's outdated ones re-queues u.
  IntegerSheet only_v;
  only_v.bundles = {v};
  only_v.deltas = {1};
  queue_.RequeueAfter(only_v);
  EXPECT_EQ(Drain(), (std::vector<BundleId>{v, w}));
}

}  // namespace
}  // namespace ispq
