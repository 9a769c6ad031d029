// SPDX-License-Identifier: Apache-2.0
// The network simplex against CLP on random networks, its optimality conditions, and the outcomes
// of infeasible, unbounded and stopped solves.
#include "core/isp/network_simplex.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "core/isp/clp_sheet_lp.h"
#include "core/lp_row_batch.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

struct Arc {
  int from, to;
  double cost, capacity;
};

struct Network {
  int num_nodes;
  std::vector<Arc> arcs;
  std::vector<double> supply;
};

// Random arcs; costs may be negative only on arcs of finite capacity (no unbounded cycle), and the
// supplies are balanced.
Network RandomNetwork(std::mt19937& random) {
  Network network;
  network.num_nodes = std::uniform_int_distribution<int>(2, 12)(random);
  std::uniform_int_distribution<int> node(0, network.num_nodes - 1);
  std::uniform_int_distribution<int> cost(-4, 9), capacity(0, 6), unlimited(0, 3);
  const int num_arcs = std::uniform_int_distribution<int>(1, 4 * network.num_nodes)(random);
  for (int k = 0; k < num_arcs; ++k) {
    Arc arc{node(random), node(random), static_cast<double>(cost(random)),
            static_cast<double>(capacity(random))};
    if (arc.from == arc.to) continue;
    if (arc.cost >= 0 && unlimited(random) == 0) arc.capacity = NetworkSimplex::kInfinity;
    network.arcs.push_back(arc);
  }
  network.supply.assign(network.num_nodes, 0);
  std::uniform_real_distribution<double> amount(0, 5);
  for (int k = 0; k < network.num_nodes / 2; ++k) {
    const double a = std::round(amount(random) * 4) / 4;  // quarters, like real weights
    network.supply[node(random)] += a;
    network.supply[node(random)] -= a;
  }
  return network;
}

// The same problem as an LP for CLP: a column per arc, a balance row per node. nullopt if CLP
// finds it infeasible.
std::optional<double> ClpOptimum(const Network& network) {
  std::unique_ptr<SheetLp> lp = NewClpSheetLp(static_cast<int>(network.arcs.size()));
  LpRowBatch rows;
  for (int v = 0; v < network.num_nodes; ++v) {
    std::vector<int32_t> columns;
    std::vector<double> coefs;
    for (int a = 0; a < static_cast<int>(network.arcs.size()); ++a) {
      if (network.arcs[a].from == v) columns.push_back(a), coefs.push_back(1);
      if (network.arcs[a].to == v) columns.push_back(a), coefs.push_back(-1);
    }
    rows.Add(columns, coefs, network.supply[v], network.supply[v]);
  }
  lp->AddRows(rows);
  for (int a = 0; a < static_cast<int>(network.arcs.size()); ++a) {
    lp->SetObjectiveCoefficient(a, network.arcs[a].cost);
    lp->SetColumnBounds(
        a, 0, std::isinf(network.arcs[a].capacity) ? kLpInfinity : network.arcs[a].capacity);
  }
  const absl::StatusOr<LpOutcome> outcome = lp->Solve();
  EXPECT_TRUE(outcome.ok()) << outcome.status();
  if (!outcome.ok() || *outcome != LpOutcome::kOptimal) return std::nullopt;
  double objective = 0;
  for (int a = 0; a < static_cast<int>(network.arcs.size()); ++a) {
    objective += network.arcs[a].cost * lp->column_values()[a];
  }
  return objective;
}

NetworkSimplex Load(const Network& network) {
  NetworkSimplex simplex(network.num_nodes);
  for (const Arc& arc : network.arcs) simplex.AddArc(arc.from, arc.to, arc.cost, arc.capacity);
  for (int v = 0; v < network.num_nodes; ++v) simplex.AddSupply(v, network.supply[v]);
  return simplex;
}

// A flow within the capacities that meets the supplies, costs CLP's optimum, and whose potentials
// prove it (complementary slackness). Arc a of the network is arc ids[a] of the simplex (a if
// ids is empty).
void ExpectOptimal(const Network& network, const NetworkSimplex& simplex, double clp_optimum,
                   const std::vector<int>& ids = {}) {
  double objective = 0;
  std::vector<double> balance(network.num_nodes, 0);
  for (int a = 0; a < static_cast<int>(network.arcs.size()); ++a) {
    const Arc& arc = network.arcs[a];
    const double flow = simplex.flow(ids.empty() ? a : ids[a]);
    objective += arc.cost * flow;
    balance[arc.from] += flow;
    balance[arc.to] -= flow;
    EXPECT_GE(flow, -1e-9);
    EXPECT_LE(flow, arc.capacity + 1e-9);
    // An arc below capacity has no negative reduced cost, an arc with flow no positive one.
    const double reduced = arc.cost + simplex.potential(arc.from) - simplex.potential(arc.to);
    if (flow < arc.capacity - 1e-9) {
      EXPECT_GE(reduced, -1e-9) << "arc " << a;
    }
    if (flow > 1e-9) {
      EXPECT_LE(reduced, 1e-9) << "arc " << a;
    }
  }
  for (int v = 0; v < network.num_nodes; ++v) EXPECT_NEAR(balance[v], network.supply[v], 1e-9);
  EXPECT_NEAR(objective, clp_optimum, 1e-7);
}

TEST(NetworkSimplexTest, FindsClpsOptimumWithPotentialsThatProveIt) {
  std::mt19937 random(11);
  int optimal = 0, infeasible = 0;
  for (int trial = 0; trial < 300; ++trial) {
    SCOPED_TRACE(trial);
    const Network network = RandomNetwork(random);
    NetworkSimplex simplex = Load(network);
    const NetworkSimplex::Outcome outcome = simplex.Solve(nullptr);
    const std::optional<double> clp = ClpOptimum(network);
    if (!clp.has_value()) {
      EXPECT_EQ(outcome, NetworkSimplex::Outcome::kInfeasible);
      ++infeasible;
      continue;
    }
    ASSERT_EQ(outcome, NetworkSimplex::Outcome::kOptimal);
    ++optimal;
    ExpectOptimal(network, simplex, *clp);
  }
  // Both kinds were drawn.
  EXPECT_GT(optimal, 50);
  EXPECT_GT(infeasible, 10);
}

// Arcs added after an optimal solve: the next solve starts from its tree and ends at the optimum
// of the whole network, also when a new arc costs more than the first solve's big M was made for
// (costs up to 40 times the first arcs'); two copies of one solved network go on independently.
TEST(NetworkSimplexTest, SolvingAgainAfterNewArcsFindsTheWholeNetworksOptimum) {
  std::mt19937 random(5);
  int resumed = 0;
  for (int trial = 0; trial < 300; ++trial) {
    SCOPED_TRACE(trial);
    const Network first = RandomNetwork(random);
    NetworkSimplex simplex = Load(first);
    if (simplex.Solve(nullptr) != NetworkSimplex::Outcome::kOptimal) continue;
    std::array<Network, 2> whole = {first, first};
    std::array<NetworkSimplex, 2> extended = {simplex, simplex};
    std::uniform_int_distribution<int> node(0, first.num_nodes - 1), cost(-360, 360);
    for (int k = 0; k < 2; ++k) {
      std::vector<int> ids(first.arcs.size());
      for (size_t a = 0; a < ids.size(); ++a) ids[a] = static_cast<int>(a);
      for (int extra = 0; extra < 3; ++extra) {
        Arc arc{node(random), node(random), static_cast<double>(cost(random)), 4};
        if (arc.from == arc.to) continue;
        if (arc.cost >= 0 && extra == 0) arc.capacity = NetworkSimplex::kInfinity;
        whole[k].arcs.push_back(arc);
        ids.push_back(extended[k].AddArc(arc.from, arc.to, arc.cost, arc.capacity));
      }
      ASSERT_EQ(extended[k].Solve(nullptr), NetworkSimplex::Outcome::kOptimal);
      const std::optional<double> clp = ClpOptimum(whole[k]);
      ASSERT_TRUE(clp.has_value());
      ExpectOptimal(whole[k], extended[k], *clp, ids);
      ++resumed;
    }
  }
  EXPECT_GT(resumed, 100);
}

TEST(NetworkSimplexTest, ANegativeCycleOfUnlimitedCapacityIsUnbounded) {
  NetworkSimplex simplex(3);
  simplex.AddArc(0, 1, 1, NetworkSimplex::kInfinity);
  simplex.AddArc(1, 2, -3, NetworkSimplex::kInfinity);
  simplex.AddArc(2, 0, 1, NetworkSimplex::kInfinity);
  EXPECT_EQ(simplex.Solve(nullptr), NetworkSimplex::Outcome::kUnbounded);
}

TEST(NetworkSimplexTest, SupplyBeyondTheCapacitiesIsInfeasible) {
  NetworkSimplex simplex(2);
  simplex.AddArc(0, 1, 1, 3);
  simplex.AddSupply(0, 5);
  simplex.AddSupply(1, -5);
  EXPECT_EQ(simplex.Solve(nullptr), NetworkSimplex::Outcome::kInfeasible);
}

TEST(NetworkSimplexTest, APivotLimitStopsTheSolve) {
  // A chain that needs a pivot per arc.
  NetworkSimplex chain(6), limited(6);
  for (NetworkSimplex* simplex : {&chain, &limited}) {
    for (int v = 0; v + 1 < 6; ++v) simplex->AddArc(v, v + 1, 1, NetworkSimplex::kInfinity);
    simplex->AddSupply(0, 2);
    simplex->AddSupply(5, -2);
  }
  EXPECT_EQ(chain.Solve(nullptr), NetworkSimplex::Outcome::kOptimal);
  EXPECT_GT(chain.pivots(), 1);
  EXPECT_EQ(limited.Solve(nullptr, 1), NetworkSimplex::Outcome::kStopped);
  EXPECT_EQ(limited.pivots(), 1);
}

}  // namespace
}  // namespace ispq
