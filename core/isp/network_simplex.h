// SPDX-License-Identifier: Apache-2.0
// A primal network simplex for min-cost flow: minimize sum cost(a) flow(a) subject to
// 0 <= flow(a) <= capacity(a) and, at every node, outflow - inflow = supply. It solves the bulk
// descent's LP on parts whose quantizations are node potentials (core/isp/sheet_network.h),
// where a general LP solver takes 30-80x longer on the same optimum (core/README.md, section The
// bulk descent as a flow).
//
// The textbook method (Ahuja, Magnanti, Orlin, "Network Flows", ch. 11): a spanning-tree basis
// rooted at an artificial node, with an artificial arc of cost M from or to every node (big-M
// start); parent and child lists per node, so that a pivot walks only the cycle it closes (its
// ends climb to their join together, marking their way) and re-hangs only the subtree it moves,
// whose potentials it shifts (no depths to keep there). Entering arcs by block search pricing (the
// most negative reduced cost within blocks of about sqrt(arcs) arcs, going round the arc list);
// leaving arcs by the strongly feasible tree rule, which rules out cycling on degenerate pivots.
//
// Arcs added after an optimal solve join at their lower bound, where the flow stays feasible, so
// the next solve goes on from that tree (core/isp/sheet_network.h prices each split of a side row
// this way, from a copy); if a new arc costs more than M was made for, M grows and the tree's
// potentials are recomputed.
//
// Potentials are the duals of the node rows: at the optimum every arc's reduced cost
// cost + potential(from) - potential(to) is >= 0 where the arc carries no flow and <= 0 where it
// is full. With integer costs they are integers, and exact in doubles (M included) while the
// sum of absolute costs along a path stays below 2^53.
#ifndef ISPQ_CORE_ISP_NETWORK_SIMPLEX_H_
#define ISPQ_CORE_ISP_NETWORK_SIMPLEX_H_

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace ispq {

class NetworkSimplex {
 public:
  static constexpr double kInfinity = std::numeric_limits<double>::infinity();

  enum class Outcome : uint8_t {
    kOptimal,
    kInfeasible,  // no flow meets the supplies within the capacities
    kUnbounded,   // a cycle of negative cost and unlimited capacity
    kStopped,     // the stop check held, or the pivot limit was reached
  };

  explicit NetworkSimplex(int num_nodes);

  int num_nodes() const { return num_nodes_; }
  int num_arcs() const { return static_cast<int>(from_.size()); }
  // capacity >= 0, or kInfinity. Returns the arc's id. Arcs may also be added after a solve
  // that ended kOptimal: the next Solve() starts from that solve's tree, where a new arc waits at
  // its lower bound (the flow stays feasible), instead of from scratch.
  int AddArc(int from, int to, double cost, double capacity);
  // Supplies are set before the first solve.
  void AddSupply(int node, double amount);

  // Solves, or after a solve that ended kOptimal and new arcs, solves again from where it ended
  // (a copy of the object keeps a tree to start several such solves from). `should_stop` is
  // asked every few thousand pivots; a solve also stops after max_pivots pivots in all (0: no
  // limit).
  Outcome Solve(const std::function<bool()>& should_stop, int64_t max_pivots = 0);

  double flow(int arc) const { return flow_[arc]; }
  double potential(int node) const { return potential_[node]; }
  int64_t pivots() const { return pivots_; }

 private:
  // The tree: each node but the root hangs from parent_ by the arc pred_arc_, which runs from the
  // node to its parent if pred_up_ (else from the parent to the node).
  void InitTree();
  // Arcs added since the last solve join at their lower bound; if one costs more than the big-M
  // start allows for, M grows and the potentials follow.
  void ResumeTree();
  int FindEnteringArc();
  // The nearest common ancestor of u and v in the tree.
  int Join(int u, int v);
  // The cycle the entering arc closes, its flow change and the leaving arc; false if unbounded.
  bool Pivot(int entering);
  void Link(int child, int parent);
  void Unlink(int child);
  // Moves the subtree of `top` (now hanging by `entering`) by the entering arc's reduced cost.
  void UpdateSubtree(int top, double shift);
  double ReducedCost(int arc) const {
    return cost_[arc] + potential_[from_[arc]] - potential_[to_[arc]];
  }

  int num_nodes_;
  int root_;
  int first_artificial_ = -1;  // the artificial arcs' ids follow, one per node; -1 before a solve
  double max_cost_ = 1;        // the largest |cost| that big_m_ covers
  double big_m_ = 0;
  bool resumable_ = false;  // the last solve ended kOptimal
  std::vector<int32_t> from_, to_;
  std::vector<double> cost_, capacity_, flow_;
  std::vector<double> supply_;
  std::vector<int8_t> state_;  // per arc: 0 in the tree, 1 at its lower bound, -1 at its upper

  std::vector<int32_t> parent_, pred_arc_, first_child_, next_sibling_, prev_sibling_;
  std::vector<uint8_t> pred_up_;
  std::vector<double> potential_;
  std::vector<int32_t> stack_;
  std::vector<int64_t> visited_;  // per node: the stamp of the last Join that passed it
  int64_t visit_stamp_ = 0;
  int next_arc_ = 0;  // where block search pricing goes on
  int block_size_ = 0;
  int64_t pivots_ = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_NETWORK_SIMPLEX_H_
