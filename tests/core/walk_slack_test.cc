// SPDX-License-Identifier: Apache-2.0
// The bounds on how far negative arcs could bring a walk back (core/walk_slack.h), on real T-meshes
// with a q of a few scattered negative arcs. That pruning by them changes no answer of the search
// is tested with the search (SeparationSearchTest.PruningByParallelSlackChangesNoAnswer); here,
// what each bound sums and how the three relate.
#include "core/walk_slack.h"

#include <algorithm>
#include <memory>
#include <vector>

#include "core/block_node_positions.h"
#include "core/parallel_classes.h"
#include "core/separation_search_tables.h"
#include "core/separation_start_configurations.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::ShortName;

// Lengths 1 to 3, and -1 on every `negative_every`-th arc.
std::vector<int64_t> ScatteredNegatives(const TMesh& mesh, int negative_every) {
  std::vector<int64_t> q(mesh.num_arcs());
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) q[a] = a % negative_every == 0 ? -1 : 1 + a % 3;
  return q;
}

// Every block placed at once, as the search places the blocks its fans reach.
struct AllBlocksPlaced {
  AllBlocksPlaced(const TMesh& mesh, SeparationSearchTables& tables, std::span<const int64_t> q)
      : positions(tables.slots().num_slots()), side_boxes(mesh.num_halfpatches()) {
    for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
      tables.slots().ComputeBlockPositions(b, q, positions);
    }
    for (HalfpatchId hp = 0; hp < mesh.num_halfpatches(); ++hp) {
      if (mesh.halfpatch_block(hp) == kNoId) continue;
      const std::span<const SlotId> cycle = tables.SideSlots(hp);
      IntBox box = PointBox(positions[cycle.front()]);
      for (const SlotId s : cycle) box = Union(box, PointBox(positions[s]));
      side_boxes[hp] = box;
    }
  }
  static IntBox Union(const IntBox& a, const IntBox& b) {
    IntBox box;
    for (int i = 0; i < 3; ++i) {
      box.lo[i] = std::min(a.lo[i], b.lo[i]);
      box.hi[i] = std::max(a.hi[i], b.hi[i]);
    }
    return box;
  }

  std::vector<IntVec3> positions;
  std::vector<IntBox> side_boxes;
};

TEST(WalkSlackTest, SumsNegativeLengthsOverTheMeshAndPerClass) {
  for (const std::string& file : RealTMeshFiles()) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    SeparationSearchTables tables(mesh);
    const std::vector<int64_t> q = ScatteredNegatives(mesh, 13);
    int64_t total = 0;
    std::vector<int64_t> per_class(tables.parallel_classes().num_classes(), 0);
    for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
      if (q[a] >= 0) continue;
      total -= q[a];
      per_class[tables.parallel_classes().of_arc(a)] -= q[a];
    }
    WalkSlack slack(mesh, tables, /*per_class=*/true);
    slack.Measure(q);
    EXPECT_EQ(slack.total(), total);
    EXPECT_EQ(slack.per_class(), per_class);

    WalkSlack whole(mesh, tables, /*per_class=*/false);
    whole.Measure(q);
    EXPECT_EQ(whole.per_class(), std::vector<int64_t>{total});
  }
}

// With no negative arc every slack is 0, so every start with branch-offs of length >= 1 is settled;
// a branch-off of length 0 is not ahead of a slack of 0.
TEST(WalkSlackTest, StartsAreSettledWhenEveryBranchOffIsLongerThanItsClassSlack) {
  for (const std::string& file : RealTMeshFiles()) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    SeparationSearchTables tables(mesh);
    std::vector<int64_t> q(mesh.num_arcs(), 1);
    WalkSlack slack(mesh, tables, /*per_class=*/true);
    slack.Measure(q);
    const SeparationStartConfigurations& configs = tables.configs();
    for (int config = 0; config < configs.size(); ++config) {
      EXPECT_TRUE(slack.AheadAtEveryBranchOff(config, q)) << "configuration " << config;
    }
    for (int config = 0; config < configs.size(); ++config) {
      if (configs.branch_offs(config).empty()) continue;
      q[ArcOf(configs.branch_offs(config).front())] = 0;
      slack.Measure(q);
      EXPECT_FALSE(slack.AheadAtEveryBranchOff(config, q)) << "configuration " << config;
      break;
    }
  }
}

// The local slack of a start never exceeds its class's (ClassBound's), and on
// scattered negatives is below the class's for some starts of most meshes: it is a sharper bound,
// not the same one. Without per-class pruning every axis gets the whole mesh's slack. These hold
// for any start box; each start gets the point at its start node (a node start's box).
TEST(WalkSlackTest, LocalSlackIsAtMostTheClassSlackAndOftenBelow) {
  int meshes_with_a_start_below = 0;
  const std::vector<std::string> files = RealTMeshFiles();
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    SeparationSearchTables tables(mesh);
    const std::vector<int64_t> q = ScatteredNegatives(mesh, 97);
    const AllBlocksPlaced placed(mesh, tables, q);
    const auto ensure = [](BlockId) {};
    const PlacedGeometry geometry = {.ensure = ensure,
                                     .positions = placed.positions.data(),
                                     .side_boxes = placed.side_boxes.data()};
    WalkSlack slack(mesh, tables, /*per_class=*/true);
    slack.Measure(q);
    WalkSlack whole(mesh, tables, /*per_class=*/false);
    whole.Measure(q);
    const ParallelClasses& classes = tables.parallel_classes();
    bool some_start_below = false;
    for (int config = 0; config < tables.configs().size(); ++config) {
      const SeparationStartConfiguration& c = tables.configs()[config];
      const IntBox start_box = PointBox({0, 0, 0});
      const std::array<int64_t, 3> bound = slack.ForStart(config, q, start_box, geometry);
      const std::array<int64_t, 3> class_bound = slack.ClassBound(config);
      for (int axis = 0; axis < 3; ++axis) {
        const int64_t class_slack = slack.per_class()[classes.of_block_axis(c.start_block, axis)];
        EXPECT_EQ(class_bound[axis], class_slack);
        EXPECT_GE(bound[axis], 0);
        EXPECT_LE(bound[axis], class_slack) << "configuration " << config;
        some_start_below |= bound[axis] < class_slack;
      }
      const std::array<int64_t, 3> whole_mesh = {whole.total(), whole.total(), whole.total()};
      EXPECT_EQ(whole.ForStart(config, q, start_box, geometry), whole_mesh);
      EXPECT_EQ(whole.ClassBound(config), whole_mesh);
    }
    meshes_with_a_start_below += some_start_below;
  }
  EXPECT_GT(2 * meshes_with_a_start_below, static_cast<int>(files.size()));
}

}  // namespace
}  // namespace ispq
