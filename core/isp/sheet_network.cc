// SPDX-License-Identifier: Apache-2.0
#include "core/isp/sheet_network.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <utility>

#include "core/disjoint_sets.h"
#include "core/isp/network_simplex.h"

namespace ispq {
namespace {

// A solve that takes more pivots than this many per arc of its network is given up (the LP
// answers): the flows of the bulk LPs measured took 0.2-0.4 pivots per arc.
constexpr int64_t kMaxPivotsPerArc = 20;
// A potential difference further than this from an integer means the solve went wrong.
constexpr double kIntegralityTolerance = 1e-6;
// Side rows are split in at most this many rounds, and only rows of at most this many terms (each
// term one more solve to price its split); past either the LP answers. The separation rows
// violated in the benchmark's separating updates were 1-3 per solve, of two terms.
constexpr int kMaxSplitRounds = 8;
constexpr size_t kMaxSplitTerms = 4;

// The smallest integer d with c * d >= rhs, for c > 0.
int64_t CeilDiv(int64_t rhs, int64_t c) { return rhs / c + (rhs % c > 0 ? 1 : 0); }

}  // namespace

SheetNetwork::SheetNetwork(const BundlePotentials& potentials, std::span<const BundleId> bundles,
                           std::span<const int32_t> local_index_of_bundle)
    : bundles_(bundles.begin(), bundles.end()), local_of_bundle_(local_index_of_bundle) {
  // Bundles of other subproblems stay as they are: their ends are one node.
  DisjointSets fixed(potentials.num_potentials());
  for (BundleId b = 0; b < static_cast<BundleId>(local_of_bundle_.size()); ++b) {
    const int32_t i = local_of_bundle_[b];
    const bool ours = i >= 0 && i < static_cast<int32_t>(bundles_.size()) && bundles_[i] == b;
    if (!ours) fixed.Join(potentials.tail(b), potentials.head(b));
  }
  std::vector<int32_t> node_of_potential(potentials.num_potentials(), kNoId);
  const auto node = [&](int32_t potential) {
    int32_t& id = node_of_potential[fixed.Find(potential)];
    if (id == kNoId) id = num_nodes_++;
    return id;
  };
  for (const BundleId b : bundles_) {
    tail_node_.push_back(node(potentials.tail(b)));
    head_node_.push_back(node(potentials.head(b)));
  }
  move_.assign(bundles_.size(), 0);
  holds_periods_ = potentials.has_handles();
}

bool SheetNetwork::AsDifference(std::span<const LinearTerm> terms, int64_t slack,
                                Difference* difference) {
  node_terms_.clear();
  for (const LinearTerm& t : terms) {
    const int32_t i = local_of_bundle_[t.var];
    node_terms_.push_back({head_node_[i], t.coef});
    node_terms_.push_back({tail_node_[i], -t.coef});
  }
  MergeRepeatedTerms(node_terms_);
  if (node_terms_.size() != 2 || node_terms_[0].coef != -node_terms_[1].coef) return false;
  // The row: c (U_to - U_from) >= -slack; an LP bound that is no integer stays a side row.
  const int64_t c = std::abs(node_terms_[0].coef);
  if (slack % c != 0) return false;
  const bool first_is_to = node_terms_[0].coef > 0;
  difference->to = node_terms_[first_is_to ? 0 : 1].var;
  difference->from = node_terms_[first_is_to ? 1 : 0].var;
  difference->rhs = -slack / c;
  return true;
}

bool SheetNetwork::SplitRow(const InequalityRows& rows, const Split& split,
                            std::vector<Difference>* differences) const {
  const std::span<const LinearTerm> terms = rows.terms(split.row);
  int64_t others = 0;
  for (int32_t k = 0; k < static_cast<int32_t>(terms.size()); ++k) {
    if (k != split.term) others += split.floors[k];
  }
  for (int32_t k = 0; k < static_cast<int32_t>(terms.size()); ++k) {
    // coef * move_b >= rhs, an integer bound on U[head] - U[tail] (a restriction: the split
    // itself is one).
    const int64_t rhs = k == split.term ? -rows.slack(split.row) - others : split.floors[k];
    const int32_t i = local_of_bundle_[terms[k].var];
    const int64_t c = terms[k].coef;
    if (tail_node_[i] == head_node_[i]) {
      if (rhs > 0) return false;
      continue;
    }
    if (c > 0) {
      differences->push_back({tail_node_[i], head_node_[i], CeilDiv(rhs, c)});
    } else {
      differences->push_back({head_node_[i], tail_node_[i], CeilDiv(rhs, -c)});
    }
  }
  return true;
}

NetworkSimplex SheetNetwork::BuildNetwork() const {
  NetworkSimplex flow(num_nodes_);
  for (size_t i = 0; i < bundles_.size(); ++i) {
    const int32_t tail = tail_node_[i], head = head_node_[i];
    if (tail == head) continue;  // its ends are merged: it cannot move
    const BundleWeights& w = weights_[i];
    flow.AddArc(tail, head, 0, std::max(0.0, w.inflate + w.deflate));
    if (std::isfinite(down_)) flow.AddArc(tail, head, down_, NetworkSimplex::kInfinity);
    if (std::isfinite(up_)) flow.AddArc(head, tail, up_, NetworkSimplex::kInfinity);
    flow.AddSupply(tail, w.inflate);
    flow.AddSupply(head, -w.inflate);
  }
  for (const Difference& d : differences_) AddDifference(d, flow);
  return flow;
}

void SheetNetwork::AddDifference(const Difference& d, NetworkSimplex& flow) {
  flow.AddArc(d.from, d.to, static_cast<double>(-d.rhs), NetworkSimplex::kInfinity);
}

SheetNetwork::Outcome SheetNetwork::SolveOnce(NetworkSimplex& flow, const LpStopCheck& should_stop,
                                              double* cost) {
  const NetworkSimplex::Outcome outcome =
      flow.Solve(should_stop, kMaxPivotsPerArc * (flow.num_arcs() + num_nodes_));
  switch (outcome) {
    case NetworkSimplex::Outcome::kOptimal:
      break;
    case NetworkSimplex::Outcome::kUnbounded:  // the dual of an infeasible LP
      return Outcome::kInfeasible;
    case NetworkSimplex::Outcome::kStopped:
      return should_stop && should_stop() ? Outcome::kStopped : Outcome::kUnanswered;
    case NetworkSimplex::Outcome::kInfeasible:  // the LP is bounded: only numerical trouble
      return Outcome::kUnanswered;
  }
  *cost = 0;
  for (size_t i = 0; i < bundles_.size(); ++i) {
    const double move = flow.potential(tail_node_[i]) - flow.potential(head_node_[i]);
    const double rounded = std::round(move);
    if (std::abs(move - rounded) > kIntegralityTolerance || rounded > up_ || -rounded > down_) {
      return Outcome::kUnanswered;
    }
    move_[i] = static_cast<int64_t>(rounded);
    *cost += rounded * (move_[i] > 0 ? weights_[i].inflate : -weights_[i].deflate);
  }
  return Outcome::kOptimal;
}

int32_t SheetNetwork::FirstViolatedSideRow(const InequalityRows& rows) const {
  for (const int32_t r : side_rows_) {
    int64_t change = 0;
    for (const LinearTerm& t : rows.terms(r)) change += t.coef * move_[local_of_bundle_[t.var]];
    if (change < -rows.slack(r)) return r;
  }
  return kNoId;
}

SheetNetwork::Outcome SheetNetwork::Solve(std::span<const BundleWeights> weights, double up,
                                          double down, const InequalityRows& rows,
                                          std::span<const int32_t> subproblem_rows,
                                          const LpStopCheck& should_stop,
                                          std::vector<std::pair<BundleId, int64_t>>* moves) {
  weights_ = weights;
  up_ = up;
  down_ = down;
  differences_.clear();
  side_rows_.clear();
  for (const int32_t r : subproblem_rows) {
    if (!rows.active(r)) continue;
    Difference d;
    if (AsDifference(rows.terms(r), rows.slack(r), &d)) {
      differences_.push_back(d);
    } else {
      side_rows_.push_back(r);
    }
  }
  // Each split adds its rows to the network its round started from; its solve starts from that
  // network's optimal tree (the base flow stays feasible), not from scratch.
  double cost = 0;
  NetworkSimplex flow = BuildNetwork();
  Outcome outcome = SolveOnce(flow, should_stop, &cost);
  // Moves with other periods may exist: the LP answers.
  if (outcome == Outcome::kInfeasible && holds_periods_) return Outcome::kUnanswered;
  std::vector<Difference> split_rows;
  for (int round = 0; outcome == Outcome::kOptimal; ++round) {
    const int32_t violated = FirstViolatedSideRow(rows);
    if (violated == kNoId) break;
    const size_t num_terms = rows.terms(violated).size();
    if (round == kMaxSplitRounds || num_terms > kMaxSplitTerms) return Outcome::kUnanswered;
    // Price each term's split; keep the cheapest.
    Split split{violated, 0, {}};
    for (const LinearTerm& t : rows.terms(violated)) {
      split.floors.push_back(t.coef * move_[local_of_bundle_[t.var]]);
    }
    double best_cost = std::numeric_limits<double>::infinity();
    std::vector<int64_t> best_move;
    std::optional<NetworkSimplex> best_flow;
    for (split.term = 0; split.term < static_cast<int32_t>(num_terms); ++split.term) {
      split_rows.clear();
      if (!SplitRow(rows, split, &split_rows)) continue;  // this split cannot hold
      NetworkSimplex trial = flow;
      for (const Difference& d : split_rows) AddDifference(d, trial);
      const Outcome split_outcome = SolveOnce(trial, should_stop, &cost);
      if (split_outcome == Outcome::kStopped) return split_outcome;
      if (split_outcome == Outcome::kOptimal && cost < best_cost) {
        best_cost = cost;
        best_move = move_;
        best_flow = std::move(trial);
      }
    }
    // No split holds: the LP may still find moves that keep the row.
    if (!best_flow.has_value()) return Outcome::kUnanswered;
    move_.swap(best_move);
    cost = best_cost;
    flow = *std::move(best_flow);
  }
  // Only the first solve can fail here, without splits: its infeasibility is the LP's.
  if (outcome != Outcome::kOptimal) return outcome;
  moves->clear();
  for (size_t i = 0; i < bundles_.size(); ++i) {
    if (move_[i] != 0) moves->push_back({bundles_[i], move_[i]});
  }
  answer_cost_ = cost;
  return Outcome::kOptimal;
}

}  // namespace ispq
