// SPDX-License-Identifier: Apache-2.0
// The sheet LP of one subproblem for a request without a root (the bulk descent's unit moves,
// SheetRequest::unit_moves, and the separating updates) solved as a min-cost flow, on meshes whose
// consistent quantizations are potential differences (core/bundle_potentials.h; core/README.md,
// section Sheet LPs as flows).
//
// Over potentials the LP reads: minimize sum_b f_b(U[head b] - U[tail b]) subject to the active
// rows, where f_b costs cp per unit up and cm per unit down (the request's weights; cp + cm >= 0,
// so f_b is convex), within -down..up (the request's box: 0, 1 or unbounded). The consistency
// rows hold by construction. A row over two potentials with opposite coefficients,
// c (U_j - U_i) >= rhs, is a difference constraint; that LP's dual is a min-cost flow (a tension
// problem, Rockafellar, "Network Flows and Monotropic Optimization", ch. 8):
//
//   per bundle, an arc tail -> head of capacity cp + cm and cost 0; an arc tail -> head of
//   unlimited capacity and cost `down` and one head -> tail of cost `up` where those are finite;
//   supply cp at the tail, -cp at the head; per difference row, an arc i -> j of unlimited
//   capacity and cost -rhs / c.
//
// The flow's optimal potentials pi are the LP's optimal U negated: move_b = pi[tail] - pi[head].
// With integer costs they are integers, so the answer is an integer sheet as it stands: no dive,
// no denominators.
//
// Rows over more potentials (a separation row over two axes) are left out of the network and
// checked on its answer: an optimum of a relaxation that satisfies them is an optimum of the LP.
// One that does not hold is split around the answer that violated it: every term but one keeps
// at least what it contributes there, and that one makes up the rest, each a difference row, which
// together imply the row; of its terms, the one whose split costs least (each priced by a solve
// that starts from the optimal tree of the network without it) is kept, until every row holds. The
// split answer is feasible for the LP but may cost more than its optimum (it is an optimum of a
// restriction); the separating updates, where such rows are violated, take it as their step, as
// they take the LP's vertex. If the splits do not settle within a few rounds, or a difference row's
// rhs is not a multiple of its coefficient, the network gives no answer and the LP is solved as
// before. Bundles outside the subproblem do not move: their potentials are merged.
//
// On parts with handles not every consistent move is a potential difference (the two sides of a
// hole may move apart): the network holds those periods at zero, so its answers there are
// feasible for the LP but not always its optimum (holds_periods()); the caller asks the LP where
// that matters (core/isp/sheet_subproblem.h), and where the flow finds no moves at all (moving a
// period might), the LP answers.
#ifndef ISPQ_CORE_ISP_SHEET_NETWORK_H_
#define ISPQ_CORE_ISP_SHEET_NETWORK_H_

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/arc_bundles.h"
#include "core/bundle_potentials.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/network_simplex.h"
#include "core/isp/sheet_lp.h"
#include "core/isp/sheet_weights.h"
#include "core/linear_terms.h"

namespace ispq {

class SheetNetwork {
 public:
  enum class Outcome : uint8_t {
    kOptimal,
    kInfeasible,  // no moves within the box satisfy the active rows
    kStopped,     // the stop check held
    kUnanswered,  // a row the network left out does not hold (or the solve gave up): ask the LP
  };

  // `bundles`: the subproblem's, ascending; `local_index_of_bundle`: per bundle of the mesh, its
  // index in its subproblem's list (SheetLpContext), kept by reference. Work O(mesh bundles), once;
  // memory O(the subproblem's bundles).
  SheetNetwork(const BundlePotentials& potentials, std::span<const BundleId> bundles,
               std::span<const int32_t> local_index_of_bundle);

  // The cheapest moves of the subproblem's bundles, each within -down..up (0, 1 or +inf), that
  // keep the active ones of `subproblem_rows`, priced by `weights` (per bundle of the subproblem,
  // in its order). On kOptimal, `moves` holds the bundles that move (ascending) and by how much.
  Outcome Solve(std::span<const BundleWeights> weights, double up, double down,
                const InequalityRows& rows, std::span<const int32_t> subproblem_rows,
                const LpStopCheck& should_stop, std::vector<std::pair<BundleId, int64_t>>* moves);
  // The cost of the last kOptimal answer, by the weights it was asked with.
  double answer_cost() const { return answer_cost_; }
  // Whether the part has handles, whose periods the answers hold at zero.
  bool holds_periods() const { return holds_periods_; }

 private:
  // A side row made to hold by its term `term` (SplitRow).
  struct Split {
    int32_t row;
    int32_t term;
    std::vector<int64_t> floors;  // per term: coef * move in the answer that violated the row
  };
  struct Difference {
    int32_t from, to;
    int64_t rhs;  // U[to] - U[from] >= rhs
  };

  // A row over nodes: a difference constraint, or a side row (false).
  bool AsDifference(std::span<const LinearTerm> terms, int64_t slack, Difference* difference);
  // The difference rows of a split: term `split.term` of the row >= -slack, every other >= 0.
  // false if one of them cannot hold (a bundle that cannot move would have to).
  bool SplitRow(const InequalityRows& rows, const Split& split,
                std::vector<Difference>* differences) const;
  // The network of the bundles' arcs and `differences_`.
  NetworkSimplex BuildNetwork() const;
  static void AddDifference(const Difference& d, NetworkSimplex& flow);
  // Solves `flow` (again, after a split's rows were added); on kOptimal, move_ and *cost hold
  // its answer.
  Outcome SolveOnce(NetworkSimplex& flow, const LpStopCheck& should_stop, double* cost);
  // The first side row that the last answer violates, or kNoId.
  int32_t FirstViolatedSideRow(const InequalityRows& rows) const;

  // Per solve: the weights, the box, the difference and side rows.
  std::span<const BundleWeights> weights_;
  double up_ = 1, down_ = 1;
  std::vector<Difference> differences_;
  std::vector<int32_t> side_rows_;

  std::vector<BundleId> bundles_;
  std::span<const int32_t> local_of_bundle_;    // per mesh bundle: its index in its subproblem
  std::vector<int32_t> tail_node_, head_node_;  // per local bundle
  int num_nodes_ = 0;
  std::vector<int64_t> move_;  // per local bundle, of the last solve
  double answer_cost_ = 0;
  bool holds_periods_ = false;
  std::vector<LinearTerm> node_terms_;  // scratch of AsDifference: terms over nodes
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_NETWORK_H_
