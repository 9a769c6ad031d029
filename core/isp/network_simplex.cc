// SPDX-License-Identifier: Apache-2.0
#include "core/isp/network_simplex.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/invariant.h"

namespace ispq {
namespace {

// Reduced costs above -kPricingTolerance do not enter (costs are integers in the engine's use,
// where every reduced cost is exact).
constexpr double kPricingTolerance = 1e-9;
// How often Solve() asks its stop check.
constexpr int64_t kPivotsPerStopCheck = 4096;

}  // namespace

NetworkSimplex::NetworkSimplex(int num_nodes)
    : num_nodes_(num_nodes), root_(num_nodes), supply_(num_nodes, 0.0) {}

int NetworkSimplex::AddArc(int from, int to, double cost, double capacity) {
  ISPQ_RELEASE_INVARIANT(from >= 0 && from < num_nodes_ && to >= 0 && to < num_nodes_,
                         "an arc between nodes of the network");
  ISPQ_RELEASE_INVARIANT(first_artificial_ < 0 || resumable_,
                         "arcs are added before a solve or after an optimal one");
  from_.push_back(from);
  to_.push_back(to);
  cost_.push_back(cost);
  capacity_.push_back(capacity);
  if (first_artificial_ >= 0) {  // waits at its lower bound
    flow_.push_back(0.0);
    state_.push_back(1);
  }
  return num_arcs() - 1;
}

void NetworkSimplex::AddSupply(int node, double amount) {
  ISPQ_RELEASE_INVARIANT(first_artificial_ < 0, "supplies are set before the first solve");
  supply_[node] += amount;
}

void NetworkSimplex::Link(int child, int parent) {
  parent_[child] = parent;
  prev_sibling_[child] = -1;
  next_sibling_[child] = first_child_[parent];
  if (first_child_[parent] >= 0) prev_sibling_[first_child_[parent]] = child;
  first_child_[parent] = child;
}

void NetworkSimplex::Unlink(int child) {
  const int parent = parent_[child];
  if (prev_sibling_[child] >= 0) {
    next_sibling_[prev_sibling_[child]] = next_sibling_[child];
  } else {
    first_child_[parent] = next_sibling_[child];
  }
  if (next_sibling_[child] >= 0) prev_sibling_[next_sibling_[child]] = prev_sibling_[child];
}

void NetworkSimplex::InitTree() {
  // Every node hangs from the root by an artificial arc of cost M that carries its supply (to the
  // root) or its demand (from it); M exceeds the cost of any path of real arcs, so the artificial
  // arcs carry flow at the optimum only where no feasible flow exists.
  for (int a = 0; a < num_arcs(); ++a) max_cost_ = std::max(max_cost_, std::abs(cost_[a]));
  big_m_ = (max_cost_ + 1) * (num_nodes_ + 1);
  first_artificial_ = num_arcs();
  const int n = num_nodes_ + 1;
  parent_.assign(n, -1);
  pred_arc_.assign(n, -1);
  visited_.assign(n, 0);
  visit_stamp_ = 0;
  first_child_.assign(n, -1);
  next_sibling_.assign(n, -1);
  prev_sibling_.assign(n, -1);
  pred_up_.assign(n, 0);
  potential_.assign(n, 0.0);
  flow_.assign(num_arcs(), 0.0);
  state_.assign(num_arcs(), 1);
  for (int v = 0; v < num_nodes_; ++v) {
    const bool gives = supply_[v] >= 0;
    from_.push_back(gives ? v : root_);
    to_.push_back(gives ? root_ : v);
    cost_.push_back(big_m_);
    capacity_.push_back(kInfinity);
    flow_.push_back(std::abs(supply_[v]));
    state_.push_back(0);
    pred_arc_[v] = num_arcs() - 1;
    pred_up_[v] = gives ? 1 : 0;
    potential_[v] = gives ? -big_m_ : big_m_;  // a zero reduced cost on the tree arc
    Link(v, root_);
  }
  block_size_ = std::max(16, static_cast<int>(std::sqrt(static_cast<double>(num_arcs()))));
  next_arc_ = 0;
}

void NetworkSimplex::ResumeTree() {
  double max_cost = max_cost_;
  for (int a = first_artificial_ + num_nodes_; a < num_arcs(); ++a) {
    max_cost = std::max(max_cost, std::abs(cost_[a]));
  }
  if (max_cost > max_cost_) {
    max_cost_ = max_cost;
    big_m_ = (max_cost_ + 1) * (num_nodes_ + 1);
    for (int a = first_artificial_; a < first_artificial_ + num_nodes_; ++a) cost_[a] = big_m_;
    // Every tree arc has reduced cost zero again: potentials from the root down.
    stack_.assign(1, root_);
    while (!stack_.empty()) {
      const int x = stack_.back();
      stack_.pop_back();
      for (int c = first_child_[x]; c >= 0; c = next_sibling_[c]) {
        const int a = pred_arc_[c];
        potential_[c] = pred_up_[c] ? potential_[x] - cost_[a] : potential_[x] + cost_[a];
        stack_.push_back(c);
      }
    }
  }
  block_size_ = std::max(16, static_cast<int>(std::sqrt(static_cast<double>(num_arcs()))));
}

int NetworkSimplex::FindEnteringArc() {
  const int m = num_arcs();
  int entering = -1;
  double best = -kPricingTolerance;
  int scanned = 0;
  for (int k = 0; k < m; ++k) {
    const int a = next_arc_;
    next_arc_ = next_arc_ + 1 == m ? 0 : next_arc_ + 1;
    const double violation = state_[a] * ReducedCost(a);
    if (violation < best) {
      best = violation;
      entering = a;
    }
    if (++scanned == block_size_) {
      if (entering >= 0) break;
      scanned = 0;
    }
  }
  return entering;
}

int NetworkSimplex::Join(int u, int v) {
  if (u == v) return u;
  // Both walk up a step at a time, marking what they pass; the first to reach a node the other
  // passed has found the join. Neither walks more than twice the longer of the two paths.
  ++visit_stamp_;
  visited_[u] = visited_[v] = visit_stamp_;
  while (true) {
    if (u != root_) {
      u = parent_[u];
      if (visited_[u] == visit_stamp_) return u;
      visited_[u] = visit_stamp_;
    }
    if (v != root_) {
      v = parent_[v];
      if (visited_[v] == visit_stamp_) return v;
      visited_[v] = visit_stamp_;
    }
  }
}

bool NetworkSimplex::Pivot(int entering) {
  // Flow goes round the cycle in the entering arc's direction if it enters from its lower bound
  // (else against it): from `first` up to the join, back down to `second`, and by the arc again.
  const bool at_lower = state_[entering] == 1;
  const int first = at_lower ? from_[entering] : to_[entering];
  const int second = at_lower ? to_[entering] : from_[entering];
  const int join = Join(first, second);
  // The leaving arc: the blocking arc met last going round the cycle from the join (first's side
  // is walked against the cycle's direction, so ties there go to the arc found first; second's
  // side along it, so ties go to the one found last). This keeps the tree strongly feasible.
  double delta = capacity_[entering];
  int leaving_node = -1;  // the node whose tree arc leaves; -1: the entering arc itself
  bool leaves_on_first_side = false;
  for (int w = first; w != join; w = parent_[w]) {
    const int a = pred_arc_[w];
    const double room = pred_up_[w] ? flow_[a] : capacity_[a] - flow_[a];
    if (room < delta) {
      delta = room;
      leaving_node = w;
      leaves_on_first_side = true;
    }
  }
  for (int w = second; w != join; w = parent_[w]) {
    const int a = pred_arc_[w];
    const double room = pred_up_[w] ? capacity_[a] - flow_[a] : flow_[a];
    if (room <= delta) {
      delta = room;
      leaving_node = w;
      leaves_on_first_side = false;
    }
  }
  if (std::isinf(delta)) return false;
  if (delta > 0) {
    flow_[entering] += state_[entering] * delta;
    for (int w = first; w != join; w = parent_[w])
      flow_[pred_arc_[w]] += pred_up_[w] ? -delta : delta;
    for (int w = second; w != join; w = parent_[w]) {
      flow_[pred_arc_[w]] += pred_up_[w] ? delta : -delta;
    }
  }
  if (leaving_node < 0) {  // the entering arc went from one bound to the other
    state_[entering] = static_cast<int8_t>(-state_[entering]);
    return true;
  }
  const int leaving = pred_arc_[leaving_node];
  state_[leaving] = flow_[leaving] <= 0 ? 1 : -1;
  if (state_[leaving] == 1) flow_[leaving] = 0;  // no rounding residue on an empty arc
  // The subtree below the leaving arc hangs again by the entering arc: reverse the tree path from
  // the entering arc's end on that side (top) up to the leaving node.
  const int top = leaves_on_first_side ? first : second;
  const int new_parent_of_top = leaves_on_first_side ? second : first;
  int w = top, new_parent = new_parent_of_top, new_pred = entering;
  uint8_t new_up = from_[entering] == top ? 1 : 0;
  while (true) {
    const int old_parent = parent_[w], old_pred = pred_arc_[w];
    const uint8_t old_up = pred_up_[w];
    Unlink(w);
    pred_arc_[w] = new_pred;
    pred_up_[w] = new_up;
    Link(w, new_parent);
    if (w == leaving_node) break;
    new_parent = w;
    new_pred = old_pred;
    new_up = old_up ? 0 : 1;
    w = old_parent;
  }
  state_[entering] = 0;
  // Potentials of the moved subtree shift so that the entering arc's reduced cost becomes zero.
  const double rc = ReducedCost(entering);
  UpdateSubtree(top, from_[entering] == top ? -rc : rc);
  return true;
}

void NetworkSimplex::UpdateSubtree(int top, double shift) {
  stack_.clear();
  stack_.push_back(top);
  while (!stack_.empty()) {
    const int x = stack_.back();
    stack_.pop_back();
    potential_[x] += shift;
    for (int c = first_child_[x]; c >= 0; c = next_sibling_[c]) stack_.push_back(c);
  }
}

NetworkSimplex::Outcome NetworkSimplex::Solve(const std::function<bool()>& should_stop,
                                              int64_t max_pivots) {
  if (first_artificial_ < 0) {
    InitTree();
  } else {
    ISPQ_RELEASE_INVARIANT(resumable_, "a network is solved again only after an optimal solve");
    ResumeTree();
  }
  resumable_ = false;
  while (true) {
    if (pivots_ % kPivotsPerStopCheck == 0 && pivots_ > 0 && should_stop && should_stop()) {
      return Outcome::kStopped;
    }
    if (max_pivots > 0 && pivots_ >= max_pivots) return Outcome::kStopped;
    const int entering = FindEnteringArc();
    if (entering < 0) break;
    ++pivots_;
    if (!Pivot(entering)) return Outcome::kUnbounded;
  }
  // Flow left on an artificial arc is supply that no real arcs can carry. The supplies are sums of
  // doubles, so a balanced network may leave rounding residue there.
  double scale = 1;
  for (int v = 0; v < num_nodes_; ++v) scale = std::max(scale, std::abs(supply_[v]));
  for (int a = first_artificial_; a < first_artificial_ + num_nodes_; ++a) {
    if (flow_[a] > 1e-9 * scale) return Outcome::kInfeasible;
  }
  resumable_ = true;
  return Outcome::kOptimal;
}

}  // namespace ispq
