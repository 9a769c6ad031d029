// SPDX-License-Identifier: Apache-2.0
// Which clean start configurations a search may skip on a new q (core/clean_starts.h), on a row
// of six unit blocks along u where the arc hops to a change are easy to count.
#include "core/clean_starts.h"

#include <array>
#include <limits>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::BuildGridTMesh;
using ::ispq::testing::GridTMesh;
using ::ispq::testing::GridTMeshSpec;
using ::ispq::testing::TMeshOrDie;

constexpr int kBlocks = 6;
// A walk bound per axis (core/walk_slack.h) for searches on q without negative lengths.
constexpr std::array<int64_t, 3> kNoSlack = {0, 0, 0};

class CleanStartsTest : public ::testing::Test {
 protected:
  CleanStartsTest() : grid_(BuildRow()), mesh_(TMeshOrDie(grid_.proto())), slots_(mesh_) {}

  static GridTMesh BuildRow() {
    GridTMeshSpec row;
    for (int i = 0; i < kBlocks; ++i) row.blocks.push_back({{i, 0, 0}, {i + 1, 1, 1}});
    absl::StatusOr<GridTMesh> grid = BuildGridTMesh(row);
    EXPECT_TRUE(grid.ok()) << grid.status();
    return *std::move(grid);
  }

  // q with every v and w interval 1 and the u intervals given.
  std::vector<int64_t> Q(const std::array<int64_t, kBlocks>& u_lengths) const {
    return grid_.QFromIntervals({{{u_lengths.begin(), u_lengths.end()}, {1}, {1}}});
  }
  NodeId Origin() const { return grid_.NodeAt({0, 0, 0}); }

  const GridTMesh grid_;
  const TMesh mesh_;
  const BlockNodeSlots slots_;
};

// The node at u = 0 is 5 arc hops from the change of the last interval (its nodes at u = 5 and
// u = 6 are dirty): a search that reached 4 hops read nothing that changed, one that reached 5 may
// have.
TEST_F(CleanStartsTest, ASearchStaysCleanIfNoChangeLiesWithinItsReach) {
  CleanStarts starts(mesh_, slots_, 3);
  starts.StartSearch(Q({1, 1, 1, 1, 1, 1}));
  starts.RecordClean(0, 4, kNoSlack);
  starts.RecordClean(1, 5, kNoSlack);
  starts.RecordClean(2, 0, kNoSlack);
  starts.StartSearch(Q({1, 1, 1, 1, 1, 2}));
  EXPECT_TRUE(starts.UnchangedSinceClean(0, Origin()));
  EXPECT_FALSE(starts.UnchangedSinceClean(1, Origin()));
  EXPECT_TRUE(starts.UnchangedSinceClean(2, Origin()));
  // Configuration 2 was not run on this q: it keeps its record, against the q before.
  starts.RecordClean(0, 4, kNoSlack);
  starts.Forget(1);
  starts.StartSearch(Q({2, 1, 1, 1, 1, 2}));
  EXPECT_FALSE(starts.UnchangedSinceClean(0, Origin()));
  EXPECT_FALSE(starts.UnchangedSinceClean(2, Origin())) << "the origin ends a changed arc";
}

// A block's positions read the arcs of its spanning tree, so a change makes every node of such a
// block dirty, even one that ends no changed arc: below two blocks stacked on one of twice their
// length, the long block's corner (2, 0, 1) ends no arc across u in [0, 1], but its position in
// that block is the sum of both u intervals.
TEST(CleanStartsOnATJunctionTest, NodesOfABlockWhosePositionsChangeAreDirty) {
  GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {2, 1, 1}}, {{0, 0, 1}, {1, 1, 2}}, {{1, 0, 1}, {2, 1, 2}}};
  const absl::StatusOr<GridTMesh> grid = BuildGridTMesh(spec);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = TMeshOrDie(grid->proto());
  const BlockNodeSlots slots(mesh);
  const auto q = [&](int64_t first_interval) {
    return grid->QFromIntervals({{{first_interval, 1}, {1}, {1, 1}}});
  };
  const NodeId corner = grid->NodeAt({2, 0, 1});
  for (HalfarcId h : mesh.outgoing_halfarcs(corner)) {
    const auto& [from, to] = grid->arc_ends(ArcOf(h));
    ASSERT_FALSE(from[0] == 0 && to[0] > 0) << "the corner ends no changed arc";
  }
  CleanStarts starts(mesh, slots, 1);
  starts.StartSearch(q(1));
  starts.RecordClean(0, 0, kNoSlack);
  starts.StartSearch(q(1));
  EXPECT_TRUE(starts.UnchangedSinceClean(0, corner));
  starts.StartSearch(q(3));
  EXPECT_FALSE(starts.UnchangedSinceClean(0, corner));
}

TEST_F(CleanStartsTest, TheSameQKeepsEveryRecord) {
  CleanStarts starts(mesh_, slots_, 1);
  const std::vector<int64_t> q = Q({1, 2, 1, 2, 1, 2});
  starts.StartSearch(q);
  EXPECT_FALSE(starts.UnchangedSinceClean(0, Origin())) << "nothing recorded yet";
  starts.RecordClean(0, CleanStarts::kMaxReach, kNoSlack);
  starts.StartSearch(q);
  EXPECT_TRUE(starts.UnchangedSinceClean(0, Origin()));
}

TEST_F(CleanStartsTest, ForgetsBeyondTheLargestReachAndWhatTheSinkStopped) {
  CleanStarts starts(mesh_, slots_, 3);
  const std::vector<int64_t> q = Q({1, 1, 1, 1, 1, 1});
  starts.StartSearch(q);
  starts.RecordClean(0, 1, kNoSlack);
  starts.RecordClean(1, 1, kNoSlack);
  starts.RecordClean(2, CleanStarts::kMaxReach + 1, kNoSlack);
  starts.StartSearch(q);
  EXPECT_TRUE(starts.UnchangedSinceClean(0, Origin()));
  EXPECT_TRUE(starts.UnchangedSinceClean(1, Origin()));
  EXPECT_FALSE(starts.UnchangedSinceClean(2, Origin()))
      << "a reach above kMaxReach is not remembered";
  starts.ForgetFrom(1);
  starts.StartSearch(q);
  EXPECT_TRUE(starts.UnchangedSinceClean(0, Origin()));
  EXPECT_FALSE(starts.UnchangedSinceClean(1, Origin()));
}

// A clean search stays clean under a bound no looser on any axis; a bound too large for the
// record is kept as the largest it can hold, which errs towards running the search again.
TEST_F(CleanStartsTest, KeepsTheWalkBoundPerAxis) {
  CleanStarts starts(mesh_, slots_, 2);
  starts.StartSearch(Q({1, 1, 1, 1, 1, 1}));
  starts.RecordClean(0, 1, {2, 0, 5});
  constexpr int64_t kHeld = std::numeric_limits<int32_t>::max();
  starts.RecordClean(1, 1, {kHeld + 7, 0, 0});
  EXPECT_TRUE(starts.BoundNoLooser(0, {2, 0, 5}));
  EXPECT_TRUE(starts.BoundNoLooser(0, {0, 0, 1}));
  EXPECT_FALSE(starts.BoundNoLooser(0, {0, 1, 0})) << "walks may get further ahead along v";
  EXPECT_FALSE(starts.BoundNoLooser(0, {3, 0, 0}));
  EXPECT_TRUE(starts.BoundNoLooser(1, {kHeld, 0, 0}));
  EXPECT_FALSE(starts.BoundNoLooser(1, {kHeld + 1, 0, 0}));
}

}  // namespace
}  // namespace ispq
