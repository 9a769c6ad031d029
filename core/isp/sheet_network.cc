// SPDX-License-Identifier: Apache-2.0
#include "core/isp/sheet_network.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <utility>

#include "core/disjoint_sets.h"
#include "core/invariant.h"
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
// Period steps per solve, and trials of one period alone per step after the halvings: each trial
// is a solve from the last optimal tree.
constexpr int kMaxPeriodSteps = 16;
constexpr size_t kMaxSinglePeriodTrials = 4;

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
  // A period is free where all its bundles are ours and can move.
  std::vector<uint8_t> period_fixed(potentials.num_periods(), 0);
  for (BundleId b = 0; b < static_cast<BundleId>(local_of_bundle_.size()); ++b) {
    const int32_t i = local_of_bundle_[b];
    const bool ours = i >= 0 && i < static_cast<int32_t>(bundles_.size()) && bundles_[i] == b;
    for (const LinearTerm& t : potentials.periods(b)) {
      if (!ours || tail_node_[i] == head_node_[i]) period_fixed[t.var] = 1;
    }
  }
  std::vector<int32_t> local_of_period(potentials.num_periods(), kNoId);
  int32_t num_periods = 0;
  std::vector<LinearTerm> terms;
  for (size_t i = 0; i < bundles_.size(); ++i) {
    terms.clear();
    for (const LinearTerm& t : potentials.periods(bundles_[i])) {
      if (period_fixed[t.var]) continue;
      if (local_of_period[t.var] == kNoId) local_of_period[t.var] = num_periods++;
      terms.push_back({local_of_period[t.var], t.coef});
    }
    if (!terms.empty()) period_bundles_.push_back(static_cast<int32_t>(i));
    local_periods_.Append(terms);
  }
  period_move_.assign(num_periods, 0);
}

bool SheetNetwork::AsDifference(std::span<const LinearTerm> terms, int64_t slack,
                                Difference* difference) {
  node_terms_.clear();
  difference->periodic = false;
  for (const LinearTerm& t : terms) {
    const int32_t i = local_of_bundle_[t.var];
    node_terms_.push_back({head_node_[i], t.coef});
    node_terms_.push_back({tail_node_[i], -t.coef});
    // sum coef * (U[head] - U[tail] + shift) >= -slack: the shifts join the slack.
    slack += t.coef * Shift(i);
    difference->periodic = difference->periodic || !local_periods_[i].empty();
  }
  MergeRepeatedTerms(node_terms_);
  if (node_terms_.size() != 2 || node_terms_[0].coef != -node_terms_[1].coef) return false;
  // The row: c (U_to - U_from) >= -slack; an LP bound that is no integer stays a side row, and so
  // does a row whose bound would be one for some P.
  const int64_t c = std::abs(node_terms_[0].coef);
  if (slack % c != 0 || (difference->periodic && c != 1)) return false;
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
    const int32_t i = local_of_bundle_[terms[k].var];
    const int64_t c = terms[k].coef;
    // coef * (U[head] - U[tail]) >= rhs - coef * shift.
    const int64_t rhs =
        (k == split.term ? -rows.slack(split.row) - others : split.floors[k]) - c * Shift(i);
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

NetworkSimplex SheetNetwork::BuildNetwork() {
  NetworkSimplex flow(num_nodes_);
  zero_arc_.assign(bundles_.size(), kNoId);
  down_arc_.assign(bundles_.size(), kNoId);
  up_arc_.assign(bundles_.size(), kNoId);
  for (size_t i = 0; i < bundles_.size(); ++i) {
    const int32_t tail = tail_node_[i], head = head_node_[i];
    if (tail == head) continue;  // its ends are merged: it cannot move
    // The move's breakpoints 0, -down and up are where the tension U[head] - U[tail] is -shift,
    // -down - shift and up - shift.
    const double shift = static_cast<double>(Shift(i));
    const BundleWeights& w = weights_[i];
    zero_arc_[i] = flow.AddArc(tail, head, shift, std::max(0.0, w.inflate + w.deflate));
    if (std::isfinite(down_)) {
      down_arc_[i] = flow.AddArc(tail, head, down_ + shift, NetworkSimplex::kInfinity);
    }
    if (std::isfinite(up_)) {
      up_arc_[i] = flow.AddArc(head, tail, up_ - shift, NetworkSimplex::kInfinity);
    }
    flow.AddSupply(tail, w.inflate);
    flow.AddSupply(head, -w.inflate);
  }
  difference_arc_.clear();
  for (const Difference& d : differences_) difference_arc_.push_back(AddDifference(d, flow));
  return flow;
}

int SheetNetwork::AddDifference(const Difference& d, NetworkSimplex& flow) {
  return flow.AddArc(d.from, d.to, static_cast<double>(-d.rhs), NetworkSimplex::kInfinity);
}

void SheetNetwork::SetPeriodCosts(const InequalityRows& rows, NetworkSimplex& flow) {
  for (const int32_t i : period_bundles_) {
    const double shift = static_cast<double>(Shift(i));
    flow.SetCost(zero_arc_[i], shift);
    if (down_arc_[i] != kNoId) flow.SetCost(down_arc_[i], down_ + shift);
    if (up_arc_[i] != kNoId) flow.SetCost(up_arc_[i], up_ - shift);
  }
  for (size_t k = 0; k < differences_.size(); ++k) {
    Difference& d = differences_[k];
    if (!d.periodic) continue;
    // Its terms and coefficients are P's at every P: only the bound moves.
    const bool still = AsDifference(rows.terms(d.row), rows.slack(d.row), &d);
    ISPQ_RELEASE_INVARIANT(still, "a periodic difference row stays one");
    flow.SetCost(difference_arc_[k], static_cast<double>(-d.rhs));
  }
}

std::vector<double> SheetNetwork::PeriodGradient(const InequalityRows& rows,
                                                 const NetworkSimplex& flow) const {
  // The LP's value is sum of cp * (tension + shift) less the flow's optimal cost, and P moves the
  // costs of its bundles' arcs (each its breakpoint: +shift on the zero and down arcs, -shift on
  // the up arc, shift = sum coef * P) and of the difference rows over them (-rhs, which holds
  // +coef * shift of each periodic term, the row's coefficient over its potentials being 1).
  std::vector<double> gradient(period_move_.size(), 0.0);
  for (const int32_t i : period_bundles_) {
    double slope = weights_[i].inflate - flow.flow(zero_arc_[i]);
    if (down_arc_[i] != kNoId) slope -= flow.flow(down_arc_[i]);
    if (up_arc_[i] != kNoId) slope += flow.flow(up_arc_[i]);
    for (const LinearTerm& t : local_periods_[i])
      gradient[t.var] += static_cast<double>(t.coef) * slope;
  }
  for (size_t k = 0; k < differences_.size(); ++k) {
    if (!differences_[k].periodic) continue;
    const double carried = flow.flow(difference_arc_[k]);
    if (carried == 0) continue;
    for (const LinearTerm& r : rows.terms(differences_[k].row)) {
      for (const LinearTerm& t : local_periods_[local_of_bundle_[r.var]]) {
        gradient[t.var] -= carried * static_cast<double>(r.coef * t.coef);
      }
    }
  }
  return gradient;
}

std::vector<std::vector<std::pair<int32_t, int64_t>>> SheetNetwork::PeriodTrials(
    const std::vector<double>& gradient, double tolerance) {
  // The periods the gradient would move, steepest first. A gradient is one subgradient at a kink
  // of the cost, not always a direction of descent: all of them are tried together, then the
  // steeper half, and so on down to the steepest alone, then the next few alone.
  std::vector<std::pair<int32_t, int64_t>> order;
  for (size_t k = 0; k < gradient.size(); ++k) {
    if (std::abs(gradient[k]) > tolerance) {
      order.push_back({static_cast<int32_t>(k), gradient[k] > 0 ? -1 : 1});
    }
  }
  std::stable_sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
    return std::abs(gradient[a.first]) > std::abs(gradient[b.first]);
  });
  std::vector<std::vector<std::pair<int32_t, int64_t>>> trials;
  for (size_t n = order.size(); n >= 1; n /= 2)
    trials.emplace_back(order.begin(), order.begin() + n);
  for (size_t k = 1; k < std::min(order.size(), kMaxSinglePeriodTrials); ++k) {
    trials.push_back({order[k]});
  }
  return trials;
}

SheetNetwork::Outcome SheetNetwork::SearchPeriods(const InequalityRows& rows,
                                                  const LpStopCheck& should_stop,
                                                  NetworkSimplex& flow, double* cost) {
  for (int step = 0; step < kMaxPeriodSteps; ++step) {
    const double tolerance = 1e-9 * (1 + std::abs(*cost));
    const std::vector<int64_t> kept_move = move_, kept_periods = period_move_;
    bool accepted = false, tried = false;
    for (const auto& trial_steps : PeriodTrials(PeriodGradient(rows, flow), tolerance)) {
      tried = true;
      for (const auto& [k, unit] : trial_steps) period_move_[k] += unit;
      NetworkSimplex trial = flow;
      SetPeriodCosts(rows, trial);
      double trial_cost = 0;
      const Outcome outcome = SolveOnce(trial, should_stop, &trial_cost);
      if (outcome == Outcome::kStopped) return outcome;
      if (outcome == Outcome::kOptimal && trial_cost < *cost - tolerance) {
        flow = std::move(trial);
        *cost = trial_cost;
        accepted = true;
        break;
      }
      period_move_ = kept_periods;
      move_ = kept_move;
    }
    if (!accepted) {
      if (tried) SetPeriodCosts(rows, flow);  // the difference rows' bounds back at the kept P
      return Outcome::kOptimal;
    }
  }
  return Outcome::kOptimal;
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
    const double move = flow.potential(tail_node_[i]) - flow.potential(head_node_[i]) +
                        static_cast<double>(Shift(i));
    const double rounded = std::round(move);
    if (std::abs(move - rounded) > kIntegralityTolerance || rounded > up_ || -rounded > down_) {
      return Outcome::kUnanswered;
    }
    move_[i] = static_cast<int64_t>(rounded);
    *cost += rounded * (move_[i] > 0 ? weights_[i].inflate : -weights_[i].deflate);
  }
  return Outcome::kOptimal;
}

void SheetNetwork::CollectRows(const InequalityRows& rows,
                               std::span<const int32_t> subproblem_rows) {
  differences_.clear();
  side_rows_.clear();
  for (const int32_t r : subproblem_rows) {
    if (!rows.active(r)) continue;
    Difference d;
    if (AsDifference(rows.terms(r), rows.slack(r), &d)) {
      d.row = r;
      differences_.push_back(d);
    } else {
      side_rows_.push_back(r);
    }
  }
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
  std::fill(period_move_.begin(), period_move_.end(), 0);
  CollectRows(rows, subproblem_rows);
  // Each split adds its rows to the network its round started from; its solve starts from that
  // network's optimal tree (the base flow stays feasible), not from scratch.
  double cost = 0;
  NetworkSimplex flow = BuildNetwork();
  Outcome outcome = SolveOnce(flow, should_stop, &cost);
  if (!period_move_.empty()) {
    // Another P may be feasible: the LP answers.
    if (outcome == Outcome::kInfeasible) return Outcome::kUnanswered;
    // An answer that descends at P = 0 is taken as it is: each trial of P copies the network
    // (searching for descending answers too took a 10^6-arc part at level 5 from 9.3 to 10.4 s
    // CPU, the same objective).
    if (outcome == Outcome::kOptimal && cost >= -1e-9 * (1 + std::abs(cost))) {
      outcome = SearchPeriods(rows, should_stop, flow, &cost);
    }
  }
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
    flow = *std::move(best_flow);
  }
  // Only the first solve can fail here, without splits: its infeasibility is the LP's.
  if (outcome != Outcome::kOptimal) return outcome;
  moves->clear();
  answer_cost_ = 0;
  for (size_t i = 0; i < bundles_.size(); ++i) {
    if (move_[i] == 0) continue;
    moves->push_back({bundles_[i], move_[i]});
    answer_cost_ +=
        static_cast<double>(move_[i]) * (move_[i] > 0 ? weights_[i].inflate : -weights_[i].deflate);
  }
  return Outcome::kOptimal;
}

}  // namespace ispq
