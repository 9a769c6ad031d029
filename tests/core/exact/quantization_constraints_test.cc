// SPDX-License-Identifier: Apache-2.0
#include "core/exact/quantization_constraints.h"

#include <cstdint>
#include <optional>
#include <set>
#include <span>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/quantization_validator.h"
#include "core/separation_row.h"
#include "core/tmesh.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

struct Problem {
  Problem(const testing::GridTMeshSpec& spec, bool per_arc_nonnegative)
      : grid(*testing::BuildGridTMesh(spec)),
        mesh(testing::TMeshOrDie(grid.proto())),
        consistency(mesh),
        bundles(mesh, consistency),
        constraints(mesh, consistency, bundles, per_arc_nonnegative) {}
  BundleId Bundle(const testing::GridPoint& a, const testing::GridPoint& b) const {
    return bundles.bundle_of(grid.ArcBetween(a, b));
  }
  testing::GridTMesh grid;
  TMesh mesh;
  ConsistencyMatrix consistency;
  ArcBundles bundles;
  QuantizationConstraints constraints;
};

// One block: bundles u, v, w (ids 0, 1, 2) of four arcs each.
testing::GridTMeshSpec Box() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  return spec;
}

// Two half-width blocks on a full-width one: the lower u width is the sum of the upper ones.
testing::GridTMeshSpec TJunction() {
  testing::GridLayout2D layout;
  layout.blocks = {{{0, 0}, {2, 1}}, {{0, 1}, {1, 2}}, {{1, 1}, {2, 2}}};
  return testing::ExtrudeLayout(layout);
}

// A block next to a taller one: one bundle (the tall block's upper w arcs on the near side) has
// no block extent row of its own.
testing::GridTMeshSpec Step() {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 2}}, {{1, 0, 0}, {2, 1, 1}}};
  return spec;
}

std::vector<int64_t> PerBundle(const Problem& p, std::vector<int64_t> x) {
  EXPECT_EQ(static_cast<int>(x.size()), p.bundles.num_bundles());
  return x;
}

// The equalities bundling leaves are the T-junction's, once, however many patches state them and
// with whichever sign (the ISP side keeps rows equal up to sign once too).
TEST(QuantizationConstraintsTest, BundlingLeavesTheTJunctionEqualityOnce) {
  const Problem box(Box(), false);
  EXPECT_EQ(box.constraints.num_equalities(), 0);
  const Problem t(TJunction(), false);
  ASSERT_EQ(t.constraints.num_equalities(), 1);
  const BundleId full = t.Bundle({0, 0, 0}, {2, 0, 0});
  const BundleId left = t.Bundle({0, 2, 0}, {1, 2, 0});
  const BundleId right = t.Bundle({1, 2, 0}, {2, 2, 0});
  std::set<std::pair<BundleId, int64_t>> terms;
  for (const LinearTerm& term : t.constraints.equality(0)) terms.insert({term.var, term.coef});
  const int64_t sign = terms.count({full, 1}) ? 1 : -1;
  EXPECT_EQ(terms,
            (std::set<std::pair<BundleId, int64_t>>{{full, sign}, {left, -sign}, {right, -sign}}));
}

// The simple rows: extents >= 0, links >= 1 (here every box edge), deduplicated over bundles.
TEST(QuantizationConstraintsTest, TheSimpleRowsAreFixedAndDeduplicated) {
  const Problem p(Box(), false);
  std::set<std::pair<std::vector<std::pair<int, int64_t>>, int64_t>> rows;
  for (int i = 0; i < p.constraints.num_inequalities(); ++i) {
    std::vector<std::pair<int, int64_t>> terms;
    for (const LinearTerm& t : p.constraints.inequality(i)) terms.push_back({t.var, t.coef});
    EXPECT_TRUE(rows.insert({terms, p.constraints.rhs(i)}).second) << "row " << i << " twice";
  }
  for (int b = 0; b < 3; ++b) EXPECT_TRUE(rows.count({{{b, 1}}, 1})) << "link row of " << b;
  EXPECT_EQ(p.constraints.num_separation_rows(), 0);
  EXPECT_TRUE(p.constraints.SatisfiesFixedRows(PerBundle(p, {1, 1, 1})));
  EXPECT_TRUE(p.constraints.SatisfiedBy(PerBundle(p, {2, 4, 1})));
  EXPECT_FALSE(p.constraints.SatisfiesFixedRows(PerBundle(p, {0, 1, 1})));
  EXPECT_FALSE(p.constraints.SatisfiesFixedRows(PerBundle(p, {1, 1, -2})));

  const Problem t(TJunction(), false);
  const BundleId full = t.Bundle({0, 0, 0}, {2, 0, 0});
  std::vector<int64_t> x(t.bundles.num_bundles(), 1);
  EXPECT_FALSE(t.constraints.SatisfiesFixedRows(x)) << "u: 1 != 1 + 1";
  x[full] = 2;
  EXPECT_TRUE(t.constraints.SatisfiesFixedRows(x));
}

// Bundle values are each bundle's first arc; arc values spread them back, and a consistent q
// round-trips.
TEST(QuantizationConstraintsTest, BundleAndArcValuesRoundTrip) {
  const Problem t(TJunction(), false);
  std::vector<int64_t> x(t.bundles.num_bundles(), 1);
  x[t.Bundle({0, 0, 0}, {2, 0, 0})] = 5;
  x[t.Bundle({0, 2, 0}, {1, 2, 0})] = 3;
  x[t.Bundle({1, 2, 0}, {2, 2, 0})] = 2;
  ASSERT_TRUE(t.constraints.SatisfiesFixedRows(x));
  const std::vector<int64_t> q = t.constraints.ArcValues(x);
  ASSERT_EQ(static_cast<int>(q.size()), t.mesh.num_arcs());
  for (ArcId a = 0; a < t.mesh.num_arcs(); ++a) EXPECT_EQ(q[a], x[t.bundles.bundle_of(a)]);
  EXPECT_EQ(t.constraints.BundleValues(q), x);
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(t.mesh, q);
  ASSERT_TRUE(report.ok());
  EXPECT_TRUE(report->consistent());
  EXPECT_TRUE(report->simple.empty());
}

// Separation rows are stored once (also when they repeat a simple row), count only the
// separation check's verdicts in SatisfiedBy, and give way to their failsafe twins on request.
TEST(QuantizationConstraintsTest, SeparationRowsAndTheirFailsafeTwins) {
  Problem p(Box(), false);
  const ArcId u = p.bundles.arcs(0)[0], u_other = p.bundles.arcs(0)[1];
  const ArcId v = p.bundles.arcs(1)[0];
  const int fixed = p.constraints.num_inequalities();
  // Repeats the link row x_u >= 1: not a new row.
  EXPECT_FALSE(p.constraints.AddSeparationRow({{{u, 1}}, 1}, std::nullopt));
  EXPECT_EQ(p.constraints.num_separation_rows(), 0);
  // x_u - x_v >= 1 with its twin x_u >= 2 (a made-up twin, to tell the forms apart).
  const SeparationRow u_over_v{{{u, 1}, {v, -1}}, 1};
  EXPECT_TRUE(p.constraints.AddSeparationRow(u_over_v, SeparationRow{{{u, 1}}, 2}));
  EXPECT_FALSE(p.constraints.AddSeparationRow(u_over_v, SeparationRow{{{u, 1}}, 2}));
  // A default row that cancels within a bundle: its twin x_u + x_u >= 1 is stored instead.
  EXPECT_TRUE(p.constraints.AddSeparationRow({{{u, 1}, {u_other, -1}}, 1},
                                             SeparationRow{{{u, 1}, {u_other, 1}}, 1}));
  EXPECT_EQ(p.constraints.num_separation_rows(), 2);
  EXPECT_EQ(p.constraints.num_inequalities(), fixed + 2);
  ASSERT_EQ(p.constraints.inequality(fixed + 1).size(), 1u);
  EXPECT_EQ(p.constraints.inequality(fixed + 1)[0].coef, 2);

  const std::vector<int64_t> u_equals_v = {1, 1, 1};
  EXPECT_TRUE(p.constraints.SatisfiesFixedRows(u_equals_v));
  EXPECT_FALSE(p.constraints.SatisfiedBy(u_equals_v));
  const std::vector<int64_t> u_above_v = {2, 1, 1};
  EXPECT_TRUE(p.constraints.SatisfiedBy(u_above_v));
  p.constraints.UseFailsafeForms();
  EXPECT_EQ(p.constraints.num_inequalities(), fixed + 2);
  EXPECT_TRUE(p.constraints.SatisfiedBy({{2, 3, 1}}));  // x_u >= 2 holds; x_u > x_v no longer asked
  EXPECT_FALSE(p.constraints.SatisfiedBy({{1, 1, 1}}));
  EXPECT_TRUE(p.constraints.SatisfiesFixedRows({{1, 1, 1}}));
}

// With the per-arc switch every bundle gets x_b >= 0, also one no block extent row covers.
TEST(QuantizationConstraintsTest, PerArcNonNegativityBoundsEveryBundle) {
  auto bounded_bundles = [](const Problem& p) {
    std::set<BundleId> bounded;
    for (int i = 0; i < p.constraints.num_inequalities(); ++i) {
      const std::span<const LinearTerm> row = p.constraints.inequality(i);
      if (row.size() == 1 && row[0].coef == 1 && p.constraints.rhs(i) == 0) {
        bounded.insert(row[0].var);
      }
    }
    return bounded;
  };
  const Problem plain(Step(), false);
  const Problem bounded(Step(), true);
  EXPECT_LT(static_cast<int>(bounded_bundles(plain).size()), plain.bundles.num_bundles());
  EXPECT_EQ(static_cast<int>(bounded_bundles(bounded).size()), bounded.bundles.num_bundles());
  EXPECT_GT(bounded.constraints.num_inequalities(), plain.constraints.num_inequalities());
}

}  // namespace
}  // namespace ispq
