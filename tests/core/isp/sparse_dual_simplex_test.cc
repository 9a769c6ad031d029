// SPDX-License-Identifier: Apache-2.0
// The sparse dual simplex (core/isp/sparse_dual_simplex.h) against CLP on long sequences of the
// edits the quantizer makes to a sheet LP, on every LP of real runs, on its own edge cases
// (degenerate and singular starts), and on what it gives up on.
#include "core/isp/sparse_dual_simplex.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/isp/clp_sheet_lp.h"
#include "core/isp/dual_simplex_sheet_lp.h"
#include "core/isp/integer_sheet_pump.h"
#include "core/isp/isp_tuning.h"
#include "core/quantization_validator.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using Status = SparseDualSimplex::Status;

// An LP's data kept beside a live solver: to build it afresh in CLP and to check answers.
struct LpModelCopy {
  struct Row {
    std::vector<int32_t> columns;
    std::vector<double> coefs;
    double lower, upper;
  };

  LpModelCopy(int num_columns, double cost)
      : cost(num_columns, cost), lower(num_columns, 0.0), upper(num_columns, kLpInfinity) {}

  void AddRows(const LpRowBatch& batch) {
    for (int i = 0; i < batch.size(); ++i) {
      const int32_t begin = batch.starts()[i], end = batch.starts()[i + 1];
      rows.push_back({{batch.columns().begin() + begin, batch.columns().begin() + end},
                      {batch.coefs().begin() + begin, batch.coefs().begin() + end},
                      batch.lower()[i],
                      batch.upper()[i]});
    }
  }
  std::unique_ptr<SheetLp> FreshClp() const {
    std::unique_ptr<SheetLp> lp = NewClpSheetLp(static_cast<int>(cost.size()));
    LpRowBatch batch;
    for (const Row& row : rows) batch.Add(row.columns, row.coefs, row.lower, row.upper);
    lp->AddRows(batch);
    for (size_t j = 0; j < cost.size(); ++j) {
      lp->SetObjectiveCoefficient(static_cast<int>(j), cost[j]);
      lp->SetColumnBounds(static_cast<int>(j), lower[j], upper[j]);
    }
    return lp;
  }
  double Objective(std::span<const double> x) const {
    double sum = 0;
    for (size_t j = 0; j < cost.size(); ++j) sum += cost[j] * x[j];
    return sum;
  }
  // The largest violation of a bound or a row by x.
  double Violation(std::span<const double> x) const {
    double worst = 0;
    for (size_t j = 0; j < cost.size(); ++j) {
      worst = std::max({worst, lower[j] - x[j], x[j] - upper[j]});
    }
    for (const Row& row : rows) {
      double activity = 0;
      for (size_t t = 0; t < row.columns.size(); ++t) activity += row.coefs[t] * x[row.columns[t]];
      worst = std::max({worst, row.lower - activity, activity - row.upper});
    }
    return worst;
  }

  std::vector<Row> rows;
  std::vector<double> cost, lower, upper;
};

// A sheet-like LP kept twice: live in the sparse simplex, and as data for fresh CLP solves.
// Columns come in pairs (Delta+ = 2b, Delta- = 2b + 1) over `bundles` bundles; rows are
// T-junction equalities x_a = x_b + x_c and inequalities over one to three bundles, written on
// both columns of each bundle as the sheet LP does.
class SheetLikeLp {
 public:
  SheetLikeLp(int bundles, const SparseDualSimplexOptions& options)
      : bundles_(bundles), simplex_(2 * bundles, options), model_(2 * bundles, 1.0) {}

  int bundles() const { return bundles_; }
  SparseDualSimplex& simplex() { return simplex_; }

  void AddRow(const std::vector<std::pair<int, double>>& bundle_terms, double lower, double upper) {
    std::vector<int32_t> columns;
    std::vector<double> coefs;
    for (const auto& [b, c] : bundle_terms) {
      columns.push_back(2 * b);
      coefs.push_back(c);
      columns.push_back(2 * b + 1);
      coefs.push_back(-c);
    }
    LpRowBatch batch;
    batch.Add(columns, coefs, lower, upper);
    simplex_.AddRows(batch);
    model_.AddRows(batch);
  }
  void SetRowLower(int row, double lower) {
    model_.rows[row].lower = lower;
    simplex_.SetRowBounds(row, lower, model_.rows[row].upper);
  }
  void SetCost(int column, double cost) {
    model_.cost[column] = cost;
    simplex_.SetObjectiveCoefficient(column, cost);
  }
  void SetBounds(int column, double lower, double upper) {
    model_.lower[column] = lower;
    model_.upper[column] = upper;
    simplex_.SetColumnBounds(column, lower, upper);
  }
  int num_rows() const { return static_cast<int>(model_.rows.size()); }
  double row_lower(int row) const { return model_.rows[row].lower; }

  // The model as it stands, built from scratch in CLP.
  std::unique_ptr<SheetLp> FreshClp() const { return model_.FreshClp(); }

  // CLP on a model built from scratch: its status, and its objective when optimal.
  std::pair<LpOutcome, double> SolveFresh() const {
    std::unique_ptr<SheetLp> lp = FreshClp();
    const absl::StatusOr<LpOutcome> outcome = lp->Solve();
    EXPECT_TRUE(outcome.ok()) << outcome.status();
    return {*outcome, *outcome == LpOutcome::kOptimal ? Objective(lp->column_values()) : 0};
  }

  double Objective(std::span<const double> x) const { return model_.Objective(x); }
  double ObjectiveScale(std::span<const double> x) const {
    double sum = 0;
    for (int j = 0; j < 2 * bundles_; ++j) sum += std::abs(model_.cost[j] * x[j]);
    return sum;
  }
  double Violation(std::span<const double> x) const { return model_.Violation(x); }

 private:
  int bundles_;
  SparseDualSimplex simplex_;
  LpModelCopy model_;
};

struct Scenario {
  uint32_t seed;
  int max_pivots;  // small values force many refactorizations
  int bundles;
};

class SparseDualSimplexVsClpTest : public ::testing::TestWithParam<Scenario> {};

// 300 rounds of quantizer-like edits: weights of a few bundles (an applied sheet) or of all (a
// new weight scheme), the root moved (bounds of two columns), sometimes a non-deflating mode, a
// blocked or pinned bundle, changed row slacks and appended rows. After each round the warm sparse
// simplex must agree with CLP from scratch on feasibility and on the optimal objective, and its
// solution must be feasible.
TEST_P(SparseDualSimplexVsClpTest, AgreesWithFreshClpOnEditSequences) {
  const int kBundles = GetParam().bundles;
  constexpr double kArcs = 1e4;  // the |A| of the tiered weights
  std::mt19937 random(GetParam().seed);
  auto uniform = [&](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(random);
  };
  auto pick = [&](int n) { return static_cast<int>(random() % n); };
  // Weights of eq. 4: toward the target (tier 1), across it (tier 2), away from it (tier 3).
  auto weight = [&]() {
    switch (pick(3)) {
      case 0:
        return uniform(0.05, 0.5);
      case 1:
        return kArcs * uniform(0.5, 1);
      default:
        return kArcs * kArcs * uniform(1, 4);
    }
  };

  SparseDualSimplexOptions options;
  options.max_pivots = GetParam().max_pivots;
  SheetLikeLp lp(kBundles, options);
  for (int j = 0; j < 2 * kBundles; ++j) lp.SetCost(j, weight());
  for (int e = 0; e < 3 * kBundles / 4; ++e) {
    const int a = pick(kBundles), b = pick(kBundles), c = pick(kBundles);
    if (a == b || b == c || a == c) continue;
    lp.AddRow({{a, 1}, {b, -1}, {c, -1}}, 0, 0);
  }
  auto add_inequality = [&]() {
    std::vector<std::pair<int, double>> terms;
    const int count = 1 + pick(3);
    for (int k = 0; k < count; ++k) terms.push_back({pick(kBundles), pick(4) == 0 ? -1.0 : 1.0});
    lp.AddRow(terms, -static_cast<double>(pick(4)), kLpInfinity);
  };
  for (int r = 0; r < 2 * kBundles / 5; ++r) add_inequality();

  int root = -1, optimal = 0, infeasible = 0;
  for (int round = 0; round < 300; ++round) {
    if (root >= 0) {  // release the last request's bounds
      for (int j = 0; j < 2 * kBundles; ++j) lp.SetBounds(j, 0, kLpInfinity);
    }
    for (int k = pick(6); k > 0; --k) lp.SetCost(pick(2 * kBundles), weight());
    if (round % 37 == 36) {  // a new objective: every weight changes (the slack basis restarts)
      for (int j = 0; j < 2 * kBundles; ++j) lp.SetCost(j, weight());
    }
    root = pick(kBundles);
    const bool inflate = pick(2) == 0;
    lp.SetBounds(2 * root + (inflate ? 0 : 1), 1, kLpInfinity);
    lp.SetBounds(2 * root + (inflate ? 1 : 0), 0, 0);
    if (pick(5) == 0) {  // non-deflating mode (eq. 7g)
      for (int b = 0; b < kBundles; ++b) {
        if (b != root) lp.SetBounds(2 * b + 1, 0, 0);
      }
    }
    if (pick(4) == 0) lp.SetBounds(2 * pick(kBundles) + pick(2), 0, 0);  // a blocked move
    if (pick(6) == 0) {                                                  // a pinned bundle
      const int b = pick(kBundles);
      if (b != root) lp.SetBounds(2 * b, 1, 1);
    }
    for (int k = pick(3); k > 0; --k) {
      const int r = pick(lp.num_rows());
      if (lp.row_lower(r) != 0 || pick(2) == 0) lp.SetRowLower(r, -static_cast<double>(pick(4)));
    }
    if (round % 50 == 49) add_inequality();

    const Status status = lp.simplex().Solve();
    ASSERT_NE(status, Status::kFailed) << "round " << round;
    const auto [expected, objective] = lp.SolveFresh();
    if (expected == LpOutcome::kInfeasible) {
      EXPECT_EQ(status, Status::kInfeasible) << "round " << round;
      ++infeasible;
      continue;
    }
    ASSERT_EQ(status, Status::kOptimal) << "round " << round;
    ++optimal;
    const std::span<const double> x = lp.simplex().column_values();
    EXPECT_LT(lp.Violation(x), 1e-7) << "round " << round;
    // What was kept incrementally is what the basis gives from scratch: the vertex is optimal.
    const SparseDualSimplex::ScratchCheck check = lp.simplex().CheckAgainstScratch();
    // (Values within the primal tolerance, 1e-8, of a bound are put on it.)
    EXPECT_LT(check.value_drift, 3e-8) << "round " << round;
    EXPECT_LT(check.primal_infeasibility, 3e-8) << "round " << round;
    EXPECT_EQ(check.dual_infeasible, 0) << "round " << round;

    // Values are exact to the primal tolerance, and weights reach 1e9: compare relative to the
    // terms of the objective.
    EXPECT_NEAR(lp.Objective(x), objective, 1e-8 * (1 + lp.ObjectiveScale(x))) << "round " << round;
  }
  // Both outcomes must have been exercised for the comparison to mean something.
  EXPECT_GT(optimal, 50);
  EXPECT_GT(infeasible, 10);
}

INSTANTIATE_TEST_SUITE_P(Sequences, SparseDualSimplexVsClpTest,
                         ::testing::Values(Scenario{1, 100, 60}, Scenario{2, 100, 60},
                                           Scenario{3, 100, 60}, Scenario{4, 3, 60},
                                           Scenario{5, 1, 60}, Scenario{6, 100, 250},
                                           Scenario{7, 17, 250}),
                         [](const auto& info) {
                           return "seed" + std::to_string(info.param.seed) + "_pivots" +
                                  std::to_string(info.param.max_pivots) + "_bundles" +
                                  std::to_string(info.param.bundles);
                         });

TEST(SparseDualSimplexTest, WithoutRowsEveryColumnSitsAtItsCheapestBound) {
  SparseDualSimplex simplex(3);
  simplex.SetObjectiveCoefficient(0, 2);
  simplex.SetColumnBounds(0, 1, 5);
  simplex.SetObjectiveCoefficient(1, -1);
  simplex.SetColumnBounds(1, 0, 4);
  simplex.SetColumnBounds(2, -2, 3);  // cost 0: anywhere; a bound is fine
  ASSERT_EQ(simplex.Solve(), Status::kOptimal);
  EXPECT_EQ(simplex.column_values()[0], 1);
  EXPECT_EQ(simplex.column_values()[1], 4);
}

TEST(SparseDualSimplexTest, ProvesAnEqualityChainInfeasible) {
  // x0 = x1 = x2 with x0 >= 1 and x2 fixed at 0.
  SparseDualSimplex simplex(3);
  LpRowBatch rows;
  rows.Add(std::vector<int32_t>{0, 1}, std::vector<double>{1, -1}, 0, 0);
  rows.Add(std::vector<int32_t>{1, 2}, std::vector<double>{1, -1}, 0, 0);
  simplex.AddRows(rows);
  for (int j = 0; j < 3; ++j) simplex.SetObjectiveCoefficient(j, 1);
  simplex.SetColumnBounds(0, 1, kLpInfinity);
  simplex.SetColumnBounds(2, 0, 0);
  EXPECT_EQ(simplex.Solve(), Status::kInfeasible);
  // Freeing x2 makes it feasible again, warm.
  simplex.SetColumnBounds(2, 0, kLpInfinity);
  ASSERT_EQ(simplex.Solve(), Status::kOptimal);
  for (int j = 0; j < 3; ++j) EXPECT_NEAR(simplex.column_values()[j], 1, 1e-12);
}

// A column whose cost turns negative with no upper bound is moved to the artificial bound; if it
// is still there at the end the LP is unbounded (or the artificial bound decided the answer),
// and the solver says it failed instead of answering.
TEST(SparseDualSimplexTest, GivesUpOnAnUnboundedLp) {
  SparseDualSimplex simplex(2);
  LpRowBatch rows;
  rows.Add(std::vector<int32_t>{0, 1}, std::vector<double>{1, -1}, 0, 0);
  simplex.AddRows(rows);
  simplex.SetObjectiveCoefficient(0, 1);
  simplex.SetObjectiveCoefficient(1, 1);
  ASSERT_EQ(simplex.Solve(), Status::kOptimal);
  simplex.SetObjectiveCoefficient(1, -3);  // x0 = x1 -> infinity lowers the objective forever
  EXPECT_EQ(simplex.Solve(), Status::kFailed);
  // With a finite bound the same LP has an answer, and the solver recovers.
  simplex.SetColumnBounds(1, 0, 10);
  ASSERT_EQ(simplex.Solve(), Status::kOptimal);
  EXPECT_NEAR(simplex.column_values()[1], 10, 1e-9);
  EXPECT_NEAR(simplex.column_values()[0], 10, 1e-9);
}

// The same: a cost change that leaves a column dual infeasible with a finite upper bound is
// repaired by moving it there, and the solve ends at the new optimum.
TEST(SparseDualSimplexTest, RepairsADualInfeasibleWarmBasis) {
  SparseDualSimplex simplex(3);
  LpRowBatch rows;
  rows.Add(std::vector<int32_t>{0, 1, 2}, std::vector<double>{1, -1, -1}, 0, 0);  // x0 = x1 + x2
  simplex.AddRows(rows);
  for (int j = 0; j < 3; ++j) {
    simplex.SetObjectiveCoefficient(j, 1);
    simplex.SetColumnBounds(j, 0, 8);
  }
  simplex.SetColumnBounds(0, 2, 8);
  ASSERT_EQ(simplex.Solve(), Status::kOptimal);
  EXPECT_NEAR(simplex.column_values()[0], 2, 1e-12);
  simplex.SetObjectiveCoefficient(2, -5);  // now x2 (and x0 with it) should go to 8
  ASSERT_EQ(simplex.Solve(), Status::kOptimal);
  EXPECT_NEAR(simplex.column_values()[0], 8, 1e-12);
  EXPECT_NEAR(simplex.column_values()[2], 8, 1e-12);
  EXPECT_NEAR(simplex.column_values()[1], 0, 1e-12);
}

// A basis CLP found optimal, adopted: the simplex confirms it without a pivot, and after a few
// costs change it goes on from there to the optimum a fresh CLP finds (the sheet LP's way back
// from a solve handed to CLP, core/isp/dual_simplex_sheet_lp.cc).
TEST(SparseDualSimplexTest, GoesOnFromAnAdoptedOptimalBasis) {
  constexpr int kBundles = 80;
  std::mt19937 random(11);
  auto pick = [&](int n) { return static_cast<int>(random() % n); };
  SheetLikeLp lp(kBundles, {});
  for (int e = 0; e < kBundles / 2; ++e) {
    const int a = pick(kBundles), b = pick(kBundles), c = pick(kBundles);
    if (a != b && b != c && a != c) lp.AddRow({{a, 1}, {b, -1}, {c, -1}}, 0, 0);
  }
  for (int r = 0; r < kBundles / 4; ++r) lp.AddRow({{pick(kBundles), 1}}, -1, kLpInfinity);
  // Unit moves as the bulk descent prices them: some improve (negative), all boxed at one unit.
  for (int j = 0; j < 2 * kBundles; ++j) {
    lp.SetBounds(j, 0, 1);
    lp.SetCost(j, std::uniform_real_distribution<double>(-3, 5)(random));
  }
  std::unique_ptr<SheetLp> clp = lp.FreshClp();
  ASSERT_EQ(*clp->Solve(), LpOutcome::kOptimal);
  const double optimum = lp.Objective(clp->column_values());
  ASSERT_LT(optimum, -1) << "some combination of moves must improve for the test to mean much";
  std::vector<uint8_t> is_basic;
  ASSERT_TRUE(clp->AppendBasis(&is_basic));
  ASSERT_EQ(is_basic.size(), static_cast<size_t>(2 * kBundles + lp.num_rows()));

  lp.simplex().AdoptBasis(is_basic, clp->column_values());
  ASSERT_EQ(lp.simplex().Solve(), Status::kOptimal);
  EXPECT_EQ(lp.simplex().iterations(), 0) << "CLP's optimal basis is optimal here too";
  EXPECT_NEAR(lp.Objective(lp.simplex().column_values()), optimum, 1e-9);
  EXPECT_LT(lp.Violation(lp.simplex().column_values()), 1e-9);

  for (int k = 0; k < 5; ++k) lp.SetCost(pick(2 * kBundles), -4);
  ASSERT_EQ(lp.simplex().Solve(), Status::kOptimal);
  const auto [expected, objective] = lp.SolveFresh();
  ASSERT_EQ(expected, LpOutcome::kOptimal);
  EXPECT_NEAR(lp.Objective(lp.simplex().column_values()), objective, 1e-9);
  EXPECT_LT(lp.Violation(lp.simplex().column_values()), 1e-9);
}

// A degenerate LP: every cost zero, so every pivot leaves the objective at zero. The solver ends
// feasible, counts the pivots as degenerate, and with the stall limit at zero gives the LP up as
// stalled instead of pivoting on (the caller's general solver then takes it).
TEST(SparseDualSimplexTest, CountsDegeneratePivotsAndGivesUpAStall) {
  auto make = [](const SparseDualSimplexOptions& options) {
    auto simplex = std::make_unique<SparseDualSimplex>(4, options);
    LpRowBatch rows;
    rows.Add(std::vector<int32_t>{0, 1}, std::vector<double>{1, 1}, 1, kLpInfinity);
    rows.Add(std::vector<int32_t>{1, 2}, std::vector<double>{1, 1}, 1, kLpInfinity);
    rows.Add(std::vector<int32_t>{2, 3}, std::vector<double>{1, 1}, 1, kLpInfinity);
    simplex->AddRows(rows);
    for (int j = 0; j < 4; ++j) simplex->SetColumnBounds(j, 0, 5);
    return simplex;
  };
  std::unique_ptr<SparseDualSimplex> simplex = make({});
  ASSERT_EQ(simplex->Solve(), Status::kOptimal);
  const std::span<const double> x = simplex->column_values();
  EXPECT_GE(x[0] + x[1], 1 - 1e-9);
  EXPECT_GE(x[1] + x[2], 1 - 1e-9);
  EXPECT_GE(x[2] + x[3], 1 - 1e-9);
  ASSERT_GT(simplex->iterations(), 0);
  EXPECT_EQ(simplex->degenerate_pivots(), simplex->iterations());
  EXPECT_EQ(simplex->stalled_solves(), 0);

  std::unique_ptr<SparseDualSimplex> stalling = make({.max_degenerate_pivots = 0});
  EXPECT_EQ(stalling->Solve(), Status::kFailed);
  EXPECT_EQ(stalling->stalled_solves(), 1);
}

// work() grows with every pivot and refactorization; a solve given less work than it needs gives
// up with kFailed, and the same solve given enough finishes.
TEST(SparseDualSimplexTest, GivesUpPastItsWorkLimit) {
  auto make = [] {
    auto simplex = std::make_unique<SparseDualSimplex>(4);
    LpRowBatch rows;
    rows.Add(std::vector<int32_t>{0, 1}, std::vector<double>{1, 1}, 1, kLpInfinity);
    rows.Add(std::vector<int32_t>{1, 2}, std::vector<double>{1, 1}, 1, kLpInfinity);
    rows.Add(std::vector<int32_t>{2, 3}, std::vector<double>{1, 1}, 1, kLpInfinity);
    simplex->AddRows(rows);
    for (int j = 0; j < 4; ++j) {
      simplex->SetColumnBounds(j, 0, 5);
      simplex->SetObjectiveCoefficient(j, 1 + j);
    }
    return simplex;
  };
  std::unique_ptr<SparseDualSimplex> unlimited = make();
  ASSERT_EQ(unlimited->Solve(), Status::kOptimal);
  ASSERT_GT(unlimited->iterations(), 1);
  const int64_t needed = unlimited->work();
  EXPECT_GT(needed, unlimited->num_rows()) << "the pivots count, not only the refactorization";

  std::unique_ptr<SparseDualSimplex> limited = make();
  EXPECT_EQ(limited->Solve(0, /*max_work=*/1), Status::kFailed);
  EXPECT_LT(limited->iterations(), unlimited->iterations());
  std::unique_ptr<SparseDualSimplex> enough = make();
  EXPECT_EQ(enough->Solve(0, /*max_work=*/needed), Status::kOptimal);
}

// A basis that is singular (two equal rows, both their logicals out of it) cannot be factorized:
// the solver falls back to the slack basis and still reaches the optimum CLP finds.
TEST(SparseDualSimplexTest, RecoversFromASingularAdoptedBasis) {
  SparseDualSimplex simplex(3);
  LpRowBatch rows;
  rows.Add(std::vector<int32_t>{0, 1}, std::vector<double>{1, 1}, 2, kLpInfinity);
  rows.Add(std::vector<int32_t>{0, 1}, std::vector<double>{1, 1}, 2, kLpInfinity);
  rows.Add(std::vector<int32_t>{1, 2}, std::vector<double>{1, -1}, 0, 0);
  simplex.AddRows(rows);
  const double cost[3] = {3, 1, 1};
  for (int j = 0; j < 3; ++j) {
    simplex.SetObjectiveCoefficient(j, cost[j]);
    simplex.SetColumnBounds(j, 0, 10);
  }
  // Columns 0 and 1 and the third row's logical basic: B has the equal rows' [1 1] twice.
  const std::vector<uint8_t> is_basic = {1, 1, 0, 0, 0, 1};
  const std::vector<double> values = {1, 1, 0};
  simplex.AdoptBasis(is_basic, values);
  ASSERT_EQ(simplex.Solve(), Status::kOptimal);
  const std::span<const double> x = simplex.column_values();
  // Optimum: x1 = x2 = 2 (cost 4) rather than x0 = 2 (cost 6).
  EXPECT_NEAR(x[0], 0, 1e-12);
  EXPECT_NEAR(x[1], 2, 1e-12);
  EXPECT_NEAR(x[2], 2, 1e-12);
}

// Every LP the quantizer solves on real T-meshes, solved twice: by the sparse dual simplex (which
// answers, so the run goes as it would) and by CLP kept alongside with the same edits. Both must
// agree on feasibility and on the optimal objective, solve by solve. Unlike the generated LPs
// above, these carry the real meshes' structure: their T-junction rows, separation rows, the
// weights' 1e-3..1e20 span, and the bulk descent's unit-move LPs.
class MirroredSheetLp : public SheetLp {
 public:
  struct Tally {
    int64_t solves = 0;
    int64_t disagreements = 0;
    int64_t warm_clp_disagreements = 0;  // settled by a fresh CLP
    std::string first_disagreement;
  };

  MirroredSheetLp(int num_columns, Tally* tally)
      : simplex_(DualSimplexSheetLpFactory(
            {.new_objective_clp_min_columns = std::numeric_limits<int>::max()})(num_columns)),
        clp_(ClpSheetLpFactory()(num_columns)),
        model_(num_columns, 0),
        tally_(tally) {}

  int num_columns() const override { return simplex_->num_columns(); }
  int num_rows() const override { return simplex_->num_rows(); }
  void SetObjectiveCoefficient(int column, double value) override {
    model_.cost[column] = value;
    simplex_->SetObjectiveCoefficient(column, value);
    clp_->SetObjectiveCoefficient(column, value);
  }
  void SetColumnBounds(int column, double lower, double upper) override {
    model_.lower[column] = lower;
    model_.upper[column] = upper;
    simplex_->SetColumnBounds(column, lower, upper);
    clp_->SetColumnBounds(column, lower, upper);
  }
  void SetRowBounds(int row, double lower, double upper) override {
    model_.rows[row].lower = lower;
    model_.rows[row].upper = upper;
    simplex_->SetRowBounds(row, lower, upper);
    clp_->SetRowBounds(row, lower, upper);
  }
  void AddRows(const LpRowBatch& batch) override {
    model_.AddRows(batch);
    simplex_->AddRows(batch);
    clp_->AddRows(batch);
  }
  bool wants_column_cap() const override { return true; }  // CLP needs it
  void SetStopCheck(LpStopCheck should_stop) override {
    simplex_->SetStopCheck(should_stop);
    clp_->SetStopCheck(std::move(should_stop));
  }

  absl::StatusOr<LpOutcome> Solve() override {
    absl::StatusOr<LpOutcome> ours = simplex_->Solve();
    ++tally_->solves;
    std::string disagreement = Disagreement(ours, clp_->Solve(), *clp_);
    if (!disagreement.empty()) {
      // The warm CLP is wrong at times (it called feasible LPs infeasible): a fresh CLP on the
      // model as it stands decides.
      ++tally_->warm_clp_disagreements;
      std::unique_ptr<SheetLp> fresh = model_.FreshClp();
      disagreement = Disagreement(ours, fresh->Solve(), *fresh);
    }
    if (!disagreement.empty() && tally_->disagreements++ == 0) {
      tally_->first_disagreement = "solve " + std::to_string(tally_->solves) + " (" +
                                   std::to_string(num_columns()) + " columns, " +
                                   std::to_string(num_rows()) + " rows): " + disagreement;
    }
    return ours;
  }
  std::span<const double> column_values() const override { return simplex_->column_values(); }

 private:
  // Empty if the two answers agree on feasibility and on the optimal objective.
  std::string Disagreement(const absl::StatusOr<LpOutcome>& ours,
                           const absl::StatusOr<LpOutcome>& theirs, const SheetLp& clp) const {
    if (!ours.ok() || !theirs.ok()) return "a back end failed";
    auto name = [](LpOutcome o) { return o == LpOutcome::kOptimal ? "optimal" : "infeasible"; };
    if (*ours != *theirs) {
      const std::span<const double> x =
          *ours == LpOutcome::kOptimal ? simplex_->column_values() : clp.column_values();
      return std::string("ours ") + name(*ours) + ", CLP " + name(*theirs) +
             "; the optimal answer violates the model by " + std::to_string(model_.Violation(x));
    }
    if (*ours != LpOutcome::kOptimal) return "";
    const double a = model_.Objective(simplex_->column_values()),
                 b = model_.Objective(clp.column_values());
    if (std::abs(a - b) <= 1e-7 * (1 + std::abs(b))) return "";
    return "objective " + std::to_string(a) + " vs CLP " + std::to_string(b);
  }

  std::unique_ptr<SheetLp> simplex_, clp_;
  LpModelCopy model_;
  Tally* tally_;
};

TEST(SparseDualSimplexTest, AgreesWithClpOnEverySheetLpOfRealMeshes) {
  MirroredSheetLp::Tally tally;
  const SheetLpFactory mirrored = [&tally](int n) {
    return std::make_unique<MirroredSheetLp>(n, &tally);
  };
  for (const char* file :
       {"hex-me/s14b_cube_corner_sub_sphere.tmesh.json", "hex-me/n06u_anti_pentapyr.tmesh.json",
        "hex-me/s06c_dodecahedron.tmesh.json",
        "singularity-constrained-fields/fanpart.tmesh.json"}) {
    const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath(file));
    for (const Level& level : mesh.levels()) {
      if (level.percent != 1 && level.percent != 25 && level.percent != 100) continue;
      QuantizeOptions options;
      options.scaling = level.scaling;
      // Root by root, as these small meshes run, and in bulk (the unit-move LPs of large ones).
      for (const int bulk_min_bundles : {IspTuning{}.bulk_descent_min_bundles, 1}) {
        IspTuning tuning;
        tuning.bulk_descent_min_bundles = bulk_min_bundles;
        const absl::StatusOr<IspOutcome> outcome =
            RunIntegerSheetPump(mesh, options, mirrored, tuning, nullptr, nullptr);
        ASSERT_TRUE(outcome.ok()) << file << " level " << level.percent << ": " << outcome.status();
        const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, outcome->q);
        ASSERT_TRUE(report.ok());
        EXPECT_TRUE(report->valid()) << file << " level " << level.percent << ":\n"
                                     << report->Describe();
      }
    }
  }
  EXPECT_GT(tally.solves, 1000) << "the runs must solve enough LPs for the test to mean much";
  EXPECT_EQ(tally.disagreements, 0)
      << "of " << tally.solves << "; first: " << tally.first_disagreement;
  std::cout << tally.solves << " LPs solved by both; the warm CLP disagreed on "
            << tally.warm_clp_disagreements << ", a fresh CLP sided with the sparse simplex\n";
}

}  // namespace
}  // namespace ispq
