// SPDX-License-Identifier: Apache-2.0
#include "core/simple_constraints.h"

#include <algorithm>
#include <vector>

#include "core/block_extents.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::RealTMeshPath;
using ::ispq::testing::ShortName;

int CountKind(const std::vector<SimpleRow>& rows, SimpleRowKind kind) {
  return static_cast<int>(std::count_if(rows.begin(), rows.end(),
                                        [kind](const SimpleRow& r) { return r.kind == kind; }));
}

std::vector<const SimpleRow*> Violated(const std::vector<SimpleRow>& rows,
                                       const std::vector<int64_t>& q) {
  std::vector<const SimpleRow*> violated;
  for (const SimpleRow& r : rows) {
    if (!r.row.IsSatisfiedBy(q)) violated.push_back(&r);
  }
  return violated;
}

// The arcs of the single cube running along `axis` (its four parallel block edges).
std::vector<ArcId> CubeArcsAlong(const TMesh& cube, int axis) {
  std::vector<ArcId> arcs;
  for (int edge = 4 * axis; edge < 4 * axis + 4; ++edge) {
    for (ArcId a : cube.block_edge_arcs(0, edge)) arcs.push_back(a);
  }
  return arcs;
}

// T1: a row's constant is its right-hand side.
TEST(SeparationRowTest, RowEncoding) {
  const SeparationRow at_least_zero{{{0, +1}}, 0};
  EXPECT_TRUE(at_least_zero.IsSatisfiedBy(std::vector<int64_t>{0}));
  EXPECT_FALSE(at_least_zero.IsSatisfiedBy(std::vector<int64_t>{-1}));
  const SeparationRow sum{{{0, +1}, {1, +1}}, 1};
  EXPECT_FALSE(sum.IsSatisfiedBy(std::vector<int64_t>{0, 0}));
  EXPECT_TRUE(sum.IsSatisfiedBy(std::vector<int64_t>{0, 1}));
  const SeparationRow difference{{{0, +1}, {1, -1}}, 1};
  EXPECT_FALSE(difference.IsSatisfiedBy(std::vector<int64_t>{1, 1}));
}

// T3: 12 link rows, 6 region rows, 3 block rows, in that order.
TEST(SimpleConstraintsTest, SingleCubeRows) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const std::vector<SimpleRow> rows = BuildSimpleRows(cube, std::nullopt);
  ASSERT_EQ(rows.size(), 21u);
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ(rows[i].kind, SimpleRowKind::kLink);
    EXPECT_EQ(cube.entity_dim(rows[i].element), EntityDim::kLink);
    ASSERT_EQ(rows[i].row.terms.size(), 1u);  // every cube edge is one link of one arc
    EXPECT_EQ(rows[i].row.terms[0].var, ArcOf(cube.entity_halfarcs(rows[i].element)[0]));
    EXPECT_EQ(rows[i].row.terms[0].coef, 1);
    EXPECT_EQ(rows[i].row.rhs, 1);
  }
  for (int i = 12; i < 18; ++i) {
    EXPECT_EQ(rows[i].kind, SimpleRowKind::kRegion);
    EXPECT_EQ(cube.entity_dim(rows[i].element), EntityDim::kRegion);
    EXPECT_EQ(rows[i].row.terms.size(), 4u);  // one square patch
    EXPECT_EQ(rows[i].row.rhs, 1);
  }
  for (int axis = 0; axis < 3; ++axis) {
    const SimpleRow& r = rows[18 + axis];
    EXPECT_EQ(r.kind, SimpleRowKind::kBlockExtent);
    EXPECT_EQ(r.element, 0);
    EXPECT_EQ(r.axis, axis);
    EXPECT_EQ(r.row.rhs, 0);
    ASSERT_EQ(r.row.terms.size(), 1u);
    EXPECT_EQ(r.row.terms[0].var, ExtentRowArcs(cube, 0, axis)[0]);
  }
}

TEST(SimpleConstraintsTest, SingleCubeViolations) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const std::vector<SimpleRow> rows = BuildSimpleRows(cube, std::nullopt);

  EXPECT_TRUE(Violated(rows, std::vector<int64_t>(12, 1)).empty());

  // q = (0, 1, 1): exactly the four u-edge links collapse.
  std::vector<int64_t> q(12, 1);
  const std::vector<ArcId> u_arcs = CubeArcsAlong(cube, 0);
  for (ArcId a : u_arcs) q[a] = 0;
  const std::vector<const SimpleRow*> violated = Violated(rows, q);
  ASSERT_EQ(violated.size(), 4u);
  for (const SimpleRow* r : violated) {
    EXPECT_EQ(r->kind, SimpleRowKind::kLink);
    EXPECT_NE(std::find(u_arcs.begin(), u_arcs.end(), r->row.terms[0].var), u_arcs.end());
  }

  // q = 0: all links and regions collapse, the block rows (>= 0) hold.
  const std::vector<const SimpleRow*> at_zero = Violated(rows, std::vector<int64_t>(12, 0));
  EXPECT_EQ(at_zero.size(), 18u);
  for (const SimpleRow* r : at_zero) EXPECT_NE(r->kind, SimpleRowKind::kBlockExtent);
}

TEST(SimpleConstraintsTest, PerArcLowerBoundRowsComeFirst) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const std::vector<SimpleRow> rows = BuildSimpleRows(cube, int64_t{0});
  ASSERT_EQ(rows.size(), 33u);
  for (ArcId a = 0; a < 12; ++a) {
    EXPECT_EQ(rows[a].kind, SimpleRowKind::kArcLowerBound);
    EXPECT_EQ(rows[a].element, a);
    EXPECT_EQ(rows[a].row, (SeparationRow{{{a, 1}}, 0}));
  }
  std::vector<int64_t> q(12, 1);
  q[5] = -1;
  const std::vector<const SimpleRow*> violated = Violated(rows, q);
  // Arc 5 breaks its bound and, as a cube edge, its link.
  ASSERT_EQ(violated.size(), 2u);
  EXPECT_EQ(violated[0]->kind, SimpleRowKind::kArcLowerBound);
  EXPECT_EQ(violated[0]->element, 5);
  EXPECT_EQ(violated[1]->kind, SimpleRowKind::kLink);
}

// On every real mesh: one row per link over its arcs, one per region over the distinct arcs of
// its patches, three per block; q = 0 collapses every link and region but no block.
TEST(SimpleConstraintsTest, RealMeshes) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    const std::vector<SimpleRow> rows = BuildSimpleRows(mesh, std::nullopt);
    int links = 0, regions = 0;
    for (EntityId e = 0; e < mesh.num_entities(); ++e) {
      links += mesh.entity_dim(e) == EntityDim::kLink;
      regions += mesh.entity_dim(e) == EntityDim::kRegion;
    }
    ASSERT_EQ(CountKind(rows, SimpleRowKind::kLink), links);
    ASSERT_EQ(CountKind(rows, SimpleRowKind::kRegion), regions);
    ASSERT_EQ(CountKind(rows, SimpleRowKind::kBlockExtent), 3 * mesh.num_blocks());
    EXPECT_EQ(CountKind(rows, SimpleRowKind::kArcLowerBound), 0);
    for (const SimpleRow& r : rows) {
      std::vector<ArcId> arcs;
      for (const LinearTerm& t : r.row.terms) {
        EXPECT_EQ(t.coef, 1);
        arcs.push_back(t.var);
      }
      std::vector<ArcId> expected;
      if (r.kind == SimpleRowKind::kLink) {
        for (HalfarcId h : mesh.entity_halfarcs(r.element)) expected.push_back(ArcOf(h));
        EXPECT_EQ(r.row.rhs, 1);
      } else if (r.kind == SimpleRowKind::kRegion) {
        for (PatchId p : mesh.entity_patches(r.element)) {
          for (HalfarcId h : mesh.patch_cycle(p)) expected.push_back(ArcOf(h));
        }
        std::sort(expected.begin(), expected.end());
        expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
        EXPECT_EQ(r.row.rhs, 1);
      } else {
        const std::span<const ArcId> edge = ExtentRowArcs(mesh, r.element, r.axis);
        expected.assign(edge.begin(), edge.end());
        EXPECT_EQ(r.row.rhs, 0);
      }
      EXPECT_EQ(arcs, expected);
    }
    const std::vector<const SimpleRow*> at_zero =
        Violated(rows, std::vector<int64_t>(mesh.num_arcs(), 0));
    EXPECT_EQ(static_cast<int>(at_zero.size()), links + regions);
  }
}

}  // namespace
}  // namespace ispq
