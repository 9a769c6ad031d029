// SPDX-License-Identifier: Apache-2.0
// The separation search on the single cube (core/README.md, section Cases with known answers, T4),
// on every real T-mesh with consistent quantizations built by elimination (invariants that every
// reported violation must satisfy, determinism T13, scale invariance), and its speed.
#include "core/separation_search.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/separation_search_tables.h"
#include "core/walk_slack.h"
#include "gtest/gtest.h"
#include "tests/bench/large/large_tmesh_generator.h"
#include "tests/support/consistent_quantizations.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::ConsistentQuantizations;
using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::RealTMeshPath;
using ::ispq::testing::ShortName;

bool SameViolation(const SeparationViolation& a, const SeparationViolation& b) {
  return a.start_entity == b.start_entity && a.sector == b.sector &&
         a.target_kind == b.target_kind && a.target == b.target && a.path == b.path &&
         a.default_row == b.default_row && a.failsafe_row == b.failsafe_row &&
         a.start_dim == b.start_dim && a.start_node == b.start_node;
}

bool SameViolations(const std::vector<SeparationViolation>& a,
                    const std::vector<SeparationViolation>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!SameViolation(a[i], b[i])) return false;
  }
  return true;
}

std::vector<ArcId> CubeArcsAlong(const TMesh& cube, int axis) {
  std::vector<ArcId> arcs;
  for (int edge = 4 * axis; edge < 4 * axis + 4; ++edge) {
    for (ArcId a : cube.block_edge_arcs(0, edge)) arcs.push_back(a);
  }
  return arcs;
}

TEST(SeparationSearchTest, UnitCubeHasNoViolations) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  SeparationSearch search(cube);
  EXPECT_TRUE(search.FindViolations(std::vector<int64_t>(12, 1)).empty());
  const std::vector<int64_t> larger = {3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3};
  EXPECT_TRUE(search.FindViolations(larger).empty());
}

// T4: with one axis collapsed, 16 rows, each a single collapsed edge arc: 8 from the corners
// (every collapsed edge twice) and one from each link along the two other axes.
TEST(SeparationSearchTest, CubeWithOneCollapsedAxis) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE(axis);
    for (BlockBoxMode mode : {BlockBoxMode::kSorted, BlockBoxMode::kReferenceUnsorted}) {
      SeparationSearch search(cube, {.block_box = mode});
      std::vector<int64_t> q(12, 1);
      const std::vector<ArcId> collapsed = CubeArcsAlong(cube, axis);
      for (ArcId a : collapsed) q[a] = 0;
      const std::vector<SeparationViolation> violations = search.FindViolations(q);
      ASSERT_EQ(violations.size(), 16u);
      std::vector<int> node_rows_per_arc(12, 0);
      std::vector<EntityId> reporting_links;
      for (const SeparationViolation& v : violations) {
        ASSERT_EQ(v.default_row.terms.size(), 1u);
        const ArcId a = v.default_row.terms[0].var;
        EXPECT_EQ(v.default_row.terms[0].coef, 1);
        EXPECT_EQ(v.default_row.rhs, 1);
        EXPECT_EQ(v.failsafe_row, v.default_row);
        EXPECT_NE(std::find(collapsed.begin(), collapsed.end(), a), collapsed.end());
        EXPECT_EQ(v.target_kind, SeparationTargetKind::kNode);
        EXPECT_EQ(v.start_dim, cube.entity_dim(v.start_entity));
        if (v.start_dim == EntityDim::kNode) {
          ++node_rows_per_arc[a];
          // The corner's sector along its collapsed edge reaches the opposite corner.
          EXPECT_EQ(v.path, std::vector<HalfarcId>{cube.outgoing_halfarcs(v.start_node)[v.sector]});
          EXPECT_EQ(v.target, cube.head(v.path[0]));
        } else {
          const HalfarcId link_arc = cube.entity_halfarcs(v.start_entity)[0];
          EXPECT_EQ(std::find(collapsed.begin(), collapsed.end(), ArcOf(link_arc)),
                    collapsed.end());
          reporting_links.push_back(v.start_entity);
        }
      }
      for (ArcId a : collapsed) EXPECT_EQ(node_rows_per_arc[a], 2);
      std::sort(reporting_links.begin(), reporting_links.end());
      EXPECT_EQ(std::unique(reporting_links.begin(), reporting_links.end()), reporting_links.end());
      EXPECT_EQ(reporting_links.size(), 8u);
    }
  }
}

// Properties every reported violation has, whatever the mesh and q: the path is a chain of
// halfarcs leaving the start entity and ending at the target; every axis the rows speak about
// has zero displacement at q, so q violates both rows, and both evaluate to exactly 0; the
// default row has coefficients +-1 and the failsafe row is its all-positive part.
void ExpectWellFormed(const TMesh& mesh, const SeparationViolation& v, std::span<const int64_t> q) {
  ASSERT_FALSE(v.path.empty());
  for (size_t i = 0; i + 1 < v.path.size(); ++i) {
    ASSERT_EQ(mesh.head(v.path[i]), mesh.tail(v.path[i + 1]));
  }
  ASSERT_EQ(v.start_dim, mesh.entity_dim(v.start_entity));
  ASSERT_EQ(v.start_node, mesh.entity_node_from(v.start_entity));
  if (v.start_dim == EntityDim::kNode) {
    EXPECT_EQ(v.path.front(), mesh.outgoing_halfarcs(v.start_node)[v.sector]);
  }
  const NodeId end = mesh.head(v.path.back());
  switch (v.target_kind) {
    case SeparationTargetKind::kNode:
      EXPECT_EQ(v.target, end);
      EXPECT_TRUE(mesh.node_critical(end));
      break;
    case SeparationTargetKind::kArc:
      EXPECT_TRUE(mesh.arc_critical(v.target));
      EXPECT_TRUE(mesh.arc_from(v.target) == end || mesh.arc_to(v.target) == end);
      break;
    case SeparationTargetKind::kPatch: {
      EXPECT_TRUE(mesh.patch_critical(v.target));
      bool on_patch = false;
      for (HalfarcId h : mesh.patch_cycle(v.target)) on_patch |= mesh.tail(h) == end;
      EXPECT_TRUE(on_patch);
      break;
    }
  }
  ASSERT_FALSE(v.default_row.terms.empty());
  ASSERT_FALSE(v.failsafe_row.terms.empty());
  EXPECT_EQ(v.default_row.rhs, 1);
  EXPECT_EQ(v.failsafe_row.rhs, 1);
  EXPECT_EQ(v.default_row.Evaluate(q), 0);
  EXPECT_EQ(v.failsafe_row.Evaluate(q), 0);
  std::vector<ArcId> seen;
  for (const LinearTerm& t : v.default_row.terms) {
    EXPECT_TRUE(t.coef == 1 || t.coef == -1);
    seen.push_back(t.var);
  }
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(std::adjacent_find(seen.begin(), seen.end()), seen.end());
  for (const LinearTerm& t : v.failsafe_row.terms) {
    EXPECT_EQ(t.coef, 1);
    EXPECT_NE(
        std::find(v.default_row.terms.begin(), v.default_row.terms.end(), LinearTerm{t.var, 1}),
        v.default_row.terms.end());
  }
}

// Consistent q with roughly half of the free arcs zero: many collapsed corridors, and negative
// arcs here and there (the search only needs consistency).
std::vector<int64_t> SparseConsistentQ(const ConsistentQuantizations& quantizations, int seed) {
  std::mt19937 random(seed);
  std::vector<int64_t> free_values;
  for (size_t i = 0; i < quantizations.free_arcs().size(); ++i) {
    free_values.push_back(static_cast<int64_t>(random() % 2));
  }
  return quantizations.Extend(free_values);
}

TEST(SeparationSearchTest, RealMeshesSparseQuantizations) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  int total = 0;
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    const ConsistentQuantizations quantizations(mesh);
    for (BlockBoxMode mode : {BlockBoxMode::kSorted, BlockBoxMode::kReferenceUnsorted}) {
      SeparationSearch search(mesh, {.block_box = mode});
      for (int seed = 1; seed <= 3; ++seed) {
        const std::vector<int64_t> q = SparseConsistentQ(quantizations, seed);
        const std::vector<SeparationViolation> violations = search.FindViolations(q);
        total += static_cast<int>(violations.size());
        for (const SeparationViolation& v : violations) ExpectWellFormed(mesh, v, q);
        // The search compares integer positions only through closed-interval tests, so a
        // positive multiple of q gives the same answer.
        std::vector<int64_t> tripled = q;
        for (int64_t& x : tripled) x *= 3;
        EXPECT_TRUE(SameViolations(search.FindViolations(tripled), violations));
      }
    }
  }
  EXPECT_GT(total, 0);
}

// All arcs zero is consistent: every critical node's sectors and every link meet something.
TEST(SeparationSearchTest, RealMeshesAllZero) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    const std::vector<int64_t> q(mesh.num_arcs(), 0);
    SeparationSearch search(mesh);
    const std::vector<SeparationViolation> violations = search.FindViolations(q);
    EXPECT_FALSE(violations.empty());
    for (const SeparationViolation& v : violations) ExpectWellFormed(mesh, v, q);
    // Only links with a zero-length start box exist here, so the first step of every node
    // sector already ends at zero distance: each critical node reports from some sector.
    std::vector<uint8_t> reported(mesh.num_entities(), 0);
    for (const SeparationViolation& v : violations) reported[v.start_entity] = 1;
    for (EntityId e = 0; e < mesh.num_entities(); ++e) {
      if (mesh.entity_dim(e) == EntityDim::kNode) {
        EXPECT_TRUE(reported[e]) << "entity " << e;
      }
    }
  }
}

// T13: the same input gives identical lists, in identical order, from the same instance and
// from a fresh one.
TEST(SeparationSearchTest, Deterministic) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (size_t i = 0; i < files.size(); i += 7) {
    SCOPED_TRACE(ShortName(files[i]));
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const ConsistentQuantizations quantizations(mesh);
    const std::vector<int64_t> q = SparseConsistentQ(quantizations, 11);
    SeparationSearch search(mesh);
    const std::vector<SeparationViolation> first = search.FindViolations(q);
    EXPECT_FALSE(first.empty());
    EXPECT_TRUE(SameViolations(search.FindViolations(q), first));
    SeparationSearch fresh(mesh);
    EXPECT_TRUE(SameViolations(fresh.FindViolations(q), first));
  }
}

// A search sharing another's mesh tables and buffers (as the two searches of
// core/separation_check.h do) answers exactly as one with its own, in either mode, also after the
// other one is gone.
TEST(SeparationSearchTest, SharingMeshTablesChangesNoAnswer) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (size_t i = 0; i < files.size(); i += 5) {
    SCOPED_TRACE(ShortName(files[i]));
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const ConsistentQuantizations quantizations(mesh);
    for (BlockBoxMode mode : {BlockBoxMode::kSorted, BlockBoxMode::kReferenceUnsorted}) {
      SeparationSearch own(mesh, {.block_box = mode});
      auto owner = std::make_unique<SeparationSearch>(mesh);
      SeparationSearch sharing(mesh, *owner, {.block_box = mode});
      owner.reset();
      for (int seed = 1; seed <= 3; ++seed) {
        const std::vector<int64_t> q = SparseConsistentQ(quantizations, seed);
        EXPECT_TRUE(SameViolations(sharing.FindViolations(q), own.FindViolations(q)));
      }
    }
  }
}

// Two searches sharing tables and buffers, called in turn on different q, answer exactly as
// searches with their own: no call sees what the other's last call left in the buffers.
TEST(SeparationSearchTest, AlternatingCallsOfSharingSearchesChangeNoAnswer) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  size_t compared = 0;  // violations, so that the test cannot pass on empty lists alone
  for (size_t i = 0; i < files.size(); i += 5) {
    SCOPED_TRACE(ShortName(files[i]));
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const ConsistentQuantizations quantizations(mesh);
    SeparationSearch own_reference(mesh, {.block_box = BlockBoxMode::kReferenceUnsorted});
    SeparationSearch own_sorted(mesh, {.block_box = BlockBoxMode::kSorted});
    SeparationSearch reference(mesh, {.block_box = BlockBoxMode::kReferenceUnsorted});
    SeparationSearch sorted(mesh, reference, {.block_box = BlockBoxMode::kSorted});
    const auto expect_same = [&](SeparationSearch& sharing, SeparationSearch& own,
                                 const std::vector<int64_t>& q) {
      const std::vector<SeparationViolation> expected = own.FindViolations(q);
      EXPECT_TRUE(SameViolations(sharing.FindViolations(q), expected));
      compared += expected.size();
    };
    for (int seed = 1; seed <= 4; ++seed) {
      const std::vector<int64_t> q = SparseConsistentQ(quantizations, seed);
      const std::vector<int64_t> other = SparseConsistentQ(quantizations, seed + 10);
      expect_same(reference, own_reference, q);
      expect_same(sorted, own_sorted, other);
      expect_same(sorted, own_sorted, q);
      expect_same(reference, own_reference, other);
    }
  }
  EXPECT_GT(compared, 0u);
}

// The mesh tables are built as searches read them and the geometry of each call only for the
// blocks it reaches (core/separation_search_tables.h): one search called on a sequence of q, in
// either order, answers every q exactly as a fresh search does, whatever earlier calls built.
TEST(SeparationSearchTest, ReusedSearchAnswersAsAFreshOneInAnyOrder) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  size_t compared = 0;  // violations, so that the test cannot pass on empty lists alone
  for (size_t i = 0; i < files.size(); i += 3) {
    SCOPED_TRACE(ShortName(files[i]));
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const ConsistentQuantizations quantizations(mesh);
    // A q with few zero arcs reaches little of the mesh; the sparse ones reach much more.
    std::vector<std::vector<int64_t>> qs = {quantizations.NearTargets(4.0)};
    for (int seed = 1; seed <= 3; ++seed) qs.push_back(SparseConsistentQ(quantizations, seed));
    for (BlockBoxMode mode : {BlockBoxMode::kSorted, BlockBoxMode::kReferenceUnsorted}) {
      std::vector<std::vector<SeparationViolation>> fresh;
      for (const std::vector<int64_t>& q : qs) {
        fresh.push_back(SeparationSearch(mesh, {.block_box = mode}).FindViolations(q));
        compared += fresh.back().size();
      }
      SeparationSearch forward(mesh, {.block_box = mode});
      for (size_t k = 0; k < qs.size(); ++k) {
        EXPECT_TRUE(SameViolations(forward.FindViolations(qs[k]), fresh[k])) << "q " << k;
      }
      SeparationSearch backward(mesh, {.block_box = mode});
      for (size_t k = qs.size(); k-- > 0;) {
        EXPECT_TRUE(SameViolations(backward.FindViolations(qs[k]), fresh[k])) << "q " << k;
      }
    }
  }
  EXPECT_GT(compared, 0u);
}

// A search skips the start configurations that came back clean on its last q and read nothing
// that changed since (core/clean_starts.h). Along sequences of q that change one free arc at a
// time (a sheet moving, as between ISP's searches), with some calls stopped after their first
// violation as ISP's rounds stop, every call answers as a fresh search on its q, and starts are
// skipped.
TEST(SeparationSearchTest, RememberedCleanStartsChangeNoAnswer) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  size_t compared = 0;
  int64_t skipped = 0;
  for (size_t i = 0; i < files.size(); i += 2) {
    SCOPED_TRACE(ShortName(files[i]));
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const ConsistentQuantizations quantizations(mesh);
    std::vector<int64_t> free_values;
    for (ArcId a : quantizations.free_arcs()) {
      free_values.push_back(std::llround(4.0 * mesh.arc_length(a)));
    }
    for (BlockBoxMode mode : {BlockBoxMode::kSorted, BlockBoxMode::kReferenceUnsorted}) {
      SeparationSearch remembering(mesh, {.block_box = mode});
      std::mt19937 random(static_cast<unsigned>(i) + 1);
      std::vector<int64_t> values = free_values;
      for (int step = 0; step < 12; ++step) {
        SCOPED_TRACE(step);
        if (step > 0) values[random() % values.size()] = static_cast<int64_t>(random() % 3);
        const std::vector<int64_t> q = quantizations.Extend(values);
        const std::vector<SeparationViolation> fresh =
            SeparationSearch(mesh, {.block_box = mode}).FindViolations(q);
        compared += fresh.size();
        if (step % 3 == 1) {
          std::vector<SeparationViolation> first;
          remembering.FindViolations(q, [&](SeparationViolation& v) {
            first.push_back(v);
            return false;
          });
          EXPECT_TRUE(SameViolations(
              first, {fresh.begin(), fresh.begin() + std::min<size_t>(1, fresh.size())}));
        }
        EXPECT_TRUE(SameViolations(remembering.FindViolations(q), fresh));
      }
      skipped += remembering.skipped_starts();
    }
  }
  EXPECT_GT(compared, 0u);
  EXPECT_GT(skipped, 0);
}

// Pruning by parallel slack (core/README.md, section Hopeless walks: walks hopeless by the negative
// lengths of their direction's class, starts settled at their branch-offs without a walk) changes
// no answer: a reused instance that prunes (so the clean-start memory sees settled starts too)
// against a fresh one that walks every start and bounds walks by the whole mesh's negative
// lengths, on q with zero, positive and (on dependent arcs) negative lengths.
TEST(SeparationSearchTest, PruningByParallelSlackChangesNoAnswer) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  size_t compared = 0;
  int64_t settled = 0;
  int negative_q = 0;
  for (size_t i = 0; i < files.size(); i += 2) {
    SCOPED_TRACE(ShortName(files[i]));
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const ConsistentQuantizations quantizations(mesh);
    for (BlockBoxMode mode : {BlockBoxMode::kSorted, BlockBoxMode::kReferenceUnsorted}) {
      SeparationSearch pruning(mesh, {.block_box = mode});
      std::mt19937 random(static_cast<unsigned>(i) + 7);
      std::vector<int64_t> values(quantizations.free_arcs().size());
      for (int64_t& x : values) x = static_cast<int64_t>(random() % 3);
      for (int step = 0; step < 8; ++step) {
        SCOPED_TRACE(step);
        if (step > 0) values[random() % values.size()] = static_cast<int64_t>(random() % 3);
        const std::vector<int64_t> q = quantizations.Extend(values);
        const std::vector<SeparationViolation> walked =
            SeparationSearch(mesh, {.block_box = mode, .prune_by_parallel_slack = false})
                .FindViolations(q);
        compared += walked.size();
        EXPECT_TRUE(SameViolations(pruning.FindViolations(q), walked));
        negative_q += *std::min_element(q.begin(), q.end()) < 0 ? 1 : 0;
      }
      settled += pruning.settled_at_branch_offs();
    }
  }
  EXPECT_GT(compared, 0u);
  EXPECT_GT(settled, 0);
  EXPECT_GT(negative_q, 0) << "some q have negative arcs, so that the slack matters";
}

// With every arc >= 1 and so no negative slack, every start is settled at its branch-offs: the
// walks, run anyway, confirm that none of them reports.
TEST(SeparationSearchTest, EveryArcAtLeastOneIsSeparating) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  int checked = 0;
  for (size_t i = 0; i < files.size(); i += 3) {
    SCOPED_TRACE(ShortName(files[i]));
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const ConsistentQuantizations quantizations(mesh);
    std::mt19937 random(static_cast<unsigned>(i) + 3);
    std::vector<int64_t> values;
    for (ArcId a : quantizations.free_arcs()) {
      values.push_back(std::max<int64_t>(1, std::llround(mesh.arc_length(a))) + random() % 2);
    }
    const std::vector<int64_t> q = quantizations.Extend(values);
    if (*std::min_element(q.begin(), q.end()) < 1) continue;  // a dependent arc came out short
    ++checked;
    for (BlockBoxMode mode : {BlockBoxMode::kSorted, BlockBoxMode::kReferenceUnsorted}) {
      EXPECT_TRUE(SeparationSearch(mesh, {.block_box = mode, .prune_by_parallel_slack = false})
                      .FindViolations(q)
                      .empty());
      SeparationSearch settling(mesh, {.block_box = mode});
      EXPECT_TRUE(settling.FindViolations(q).empty());
      EXPECT_GT(settling.settled_at_branch_offs(), 0);
    }
  }
  EXPECT_GT(checked, 5);
}

// On a part with one frame (core/global_frame.h) and a q with a few negative arcs, a start none of
// whose blocks' boxes touches a block around one is bounded by zero without placing blocks
// (core/walk_slack.h). On an assembly part along a sequence of such q (grid intervals of 1 to 4,
// a few of -1 moving between calls): a fresh search settles more starts at their branch-offs
// than the classes' slack alone would, and a remembering search answers every q as a fresh one
// that walks every start under the whole mesh's slack.
TEST(SeparationSearchTest, StartsAwayFromNegativeArcsAreBoundedByZero) {
  const absl::StatusOr<testing::GridTMesh> grid =
      bench::BuildLargeTMesh(bench::LargeFamily::kAssembly16, 3000, 5);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = testing::TMeshOrDie(grid->proto());
  std::array<std::vector<int64_t>, 3> intervals;
  for (NodeId n = 0; n < mesh.num_nodes(); ++n) {
    for (int axis = 0; axis < 3; ++axis) {
      const size_t extent = static_cast<size_t>(grid->node_point(n)[axis]);
      if (intervals[axis].size() < extent) intervals[axis].resize(extent);
    }
  }
  std::mt19937 random(11);
  for (auto& axis : intervals) {
    for (int64_t& length : axis) length = 1 + static_cast<int64_t>(random() % 4);
  }
  size_t compared = 0;
  int more_settled = 0;
  for (BlockBoxMode mode : {BlockBoxMode::kSorted, BlockBoxMode::kReferenceUnsorted}) {
    SeparationSearch remembering(mesh, {.block_box = mode});
    for (int step = 0; step < 6; ++step) {
      SCOPED_TRACE(step);
      std::array<std::vector<int64_t>, 3> negative = intervals;
      for (int k = 0; k < 2; ++k) {
        std::vector<int64_t>& axis = negative[random() % 3];
        axis[random() % axis.size()] = -1;
      }
      const std::vector<int64_t> q = grid->QFromIntervals(negative);
      const int64_t negative_arcs =
          std::count_if(q.begin(), q.end(), [](int64_t x) { return x < 0; });
      const std::vector<SeparationViolation> walked =
          SeparationSearch(mesh, {.block_box = mode, .prune_by_parallel_slack = false})
              .FindViolations(q);
      compared += walked.size();
      EXPECT_TRUE(SameViolations(remembering.FindViolations(q), walked));
      if (negative_arcs == 0) continue;
      SeparationSearchTables tables(mesh);
      WalkSlack slack(mesh, tables, /*per_class=*/true);
      slack.Measure(q);
      int64_t settled_by_class = 0;
      for (int config = 0; config < tables.configs().size(); ++config) {
        settled_by_class += slack.AheadAtEveryBranchOff(config, q) ? 1 : 0;
      }
      SeparationSearch fresh(mesh, {.block_box = mode});
      EXPECT_TRUE(SameViolations(fresh.FindViolations(q), walked));
      more_settled += fresh.settled_at_branch_offs() > settled_by_class ? 1 : 0;
    }
  }
  EXPECT_GT(compared, 0u);
  EXPECT_GT(more_settled, 6);
}

}  // namespace
}  // namespace ispq
