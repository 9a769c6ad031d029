// SPDX-License-Identifier: Apache-2.0
// The separation search's mesh tables, built on demand: every list says what the mesh says, and
// a list is the same whichever lists were built before it.
#include "core/separation_search_tables.h"

#include <algorithm>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::RealTMeshPath;
using ::ispq::testing::ShortName;

template <typename T>
std::vector<T> Copy(std::span<const T> list) {
  return {list.begin(), list.end()};
}

// Every list of the tables, asked for in ascending or descending id order.
struct AllLists {
  AllLists(const TMesh& mesh, SeparationSearchTables& tables, bool descending) {
    const auto each = [descending](int count, const auto& visit) {
      for (int k = 0; k < count; ++k) visit(descending ? count - 1 - k : k);
    };
    outgoing.resize(mesh.num_nodes());
    critical_sides.resize(mesh.num_nodes());
    halfarc_blocks.resize(mesh.num_halfarcs());
    fan_crossings.resize(tables.slots().num_slots());
    side_slots.resize(mesh.num_halfpatches());
    each(mesh.num_halfpatches(), [&](int hp) { side_slots[hp] = Copy(tables.SideSlots(hp)); });
    each(tables.slots().num_slots(),
         [&](int s) { fan_crossings[s] = Copy(tables.FanCrossings(s)); });
    each(mesh.num_halfarcs(), [&](int h) { halfarc_blocks[h] = Copy(tables.HalfarcBlocks(h)); });
    each(mesh.num_nodes(), [&](int n) {
      critical_sides[n] = Copy(tables.CriticalSides(n));
      outgoing[n] = Copy(tables.SortedOutgoing(n));
    });
  }
  std::vector<std::vector<HalfarcId>> outgoing;
  std::vector<std::vector<CriticalSide>> critical_sides;
  std::vector<std::vector<HalfarcInBlock>> halfarc_blocks;
  std::vector<std::vector<FanCrossing>> fan_crossings;
  std::vector<std::vector<SlotId>> side_slots;
};

TEST(SeparationSearchTablesTest, ListsDoNotDependOnTheOrderTheyWereBuiltIn) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    SeparationSearchTables ascending_tables(mesh), descending_tables(mesh);
    const AllLists ascending(mesh, ascending_tables, false);
    const AllLists descending(mesh, descending_tables, true);
    EXPECT_EQ(ascending.outgoing, descending.outgoing);
    EXPECT_EQ(ascending.critical_sides, descending.critical_sides);
    EXPECT_EQ(ascending.halfarc_blocks, descending.halfarc_blocks);
    EXPECT_EQ(ascending.fan_crossings, descending.fan_crossings);
    EXPECT_EQ(ascending.side_slots, descending.side_slots);
  }
}

// What each list holds, checked against the mesh's own adjacency on every real T-mesh.
TEST(SeparationSearchTablesTest, ListsAgreeWithTheMesh) {
  for (const std::string& file : RealTMeshFiles()) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    SeparationSearchTables tables(mesh);
    const BlockNodeSlots& slots = tables.slots();
    for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
      std::vector<HalfarcId> expected(mesh.outgoing_halfarcs(n).begin(),
                                      mesh.outgoing_halfarcs(n).end());
      std::sort(expected.begin(), expected.end());
      EXPECT_EQ(Copy(tables.SortedOutgoing(n)), expected);
      for (const CriticalSide& side : tables.CriticalSides(n)) {
        EXPECT_TRUE(mesh.patch_critical(PatchOf(side.side)));
        EXPECT_EQ(slots.block_of(side.slot), mesh.halfpatch_block(side.side));
        EXPECT_EQ(slots.node_of(side.slot), n);
      }
    }
    for (HalfarcId h = 0; h < mesh.num_halfarcs(); ++h) {
      const std::span<const HalfarcInBlock> entries = tables.HalfarcBlocks(h);
      EXPECT_EQ(entries.size(), mesh.arc_blocks(ArcOf(h)).size());
      for (const HalfarcInBlock& entry : entries) {
        EXPECT_EQ(entry.dir, mesh.HalfarcDirInBlock(h, entry.block));
        EXPECT_EQ(entry.head_slot, slots.Find(entry.block, mesh.head(h)));
      }
    }
    for (HalfpatchId hp = 0; hp < mesh.num_halfpatches(); ++hp) {
      const std::span<const SlotId> cycle = tables.SideSlots(hp);
      if (mesh.halfpatch_block(hp) == kNoId) {
        EXPECT_TRUE(cycle.empty());
        continue;
      }
      ASSERT_EQ(static_cast<int>(cycle.size()), mesh.halfpatch_cycle_size(hp));
      for (int i = 0; i < static_cast<int>(cycle.size()); ++i) {
        EXPECT_EQ(slots.block_of(cycle[i]), mesh.halfpatch_block(hp));
        EXPECT_EQ(slots.node_of(cycle[i]), mesh.tail(mesh.HalfpatchCycleAt(hp, i)));
      }
    }
    for (SlotId s = 0; s < slots.num_slots(); ++s) {
      for (const FanCrossing& crossing : tables.FanCrossings(s)) {
        EXPECT_EQ(mesh.halfpatch_block(crossing.side), slots.block_of(s));
        const std::span<const HalfpatchId> at_node = mesh.node_halfpatches(slots.node_of(s));
        EXPECT_TRUE(std::binary_search(at_node.begin(), at_node.end(), crossing.side));
        if (crossing.neighbor_slot == kNoId) {
          EXPECT_EQ(mesh.halfpatch_block(crossing.side ^ 1), kNoId);
        } else {
          EXPECT_EQ(slots.block_of(crossing.neighbor_slot),
                    mesh.halfpatch_block(crossing.side ^ 1));
          EXPECT_EQ(slots.node_of(crossing.neighbor_slot), slots.node_of(s));
        }
      }
    }
  }
}

// Asking for a list builds that list alone, except a block's side slots, which come with all the
// sides of their block; asking again builds nothing.
TEST(SeparationSearchTablesTest, BuildsOnlyWhatIsAskedFor) {
  const TMesh mesh =
      LoadTMeshOrDie(RealTMeshPath("singularity-constrained-fields/fanpart.tmesh.json"));
  SeparationSearchTables tables(mesh);
  EXPECT_EQ(tables.num_built_values(), 0u);
  size_t built = tables.HalfarcBlocks(0).size();
  EXPECT_EQ(tables.num_built_values(), built);
  tables.HalfarcBlocks(0);
  EXPECT_EQ(tables.num_built_values(), built);
  built += tables.SortedOutgoing(0).size();
  EXPECT_EQ(tables.num_built_values(), built);
  built += tables.FanCrossings(tables.slots().first_slot(0)).size();
  EXPECT_EQ(tables.num_built_values(), built);
  built += tables.CriticalSides(0).size();
  EXPECT_EQ(tables.num_built_values(), built);

  HalfpatchId owned = kNoId;
  for (const HalfpatchId side : mesh.block_halfpatches(0)) {
    if (mesh.halfpatch_block(side) == 0) owned = side;
  }
  ASSERT_NE(owned, kNoId);
  tables.SideSlots(owned);
  size_t block_side_slots = 0;
  for (const HalfpatchId side : mesh.block_halfpatches(0)) {
    if (mesh.halfpatch_block(side) == 0) block_side_slots += mesh.halfpatch_cycle_size(side);
  }
  EXPECT_EQ(tables.num_built_values(), built + block_side_slots);
}

}  // namespace
}  // namespace ispq
