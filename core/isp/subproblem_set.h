// SPDX-License-Identifier: Apache-2.0
// The subproblems of one ISP run (paper section 4.4; core/README.md, section Bundles and
// subproblems) and their sheet LPs.
//
// A run starts with one subproblem per connected component of the bundles under the
// consistency and block-extent rows (core/subproblems.h), or a single one without
// decomposition, each with its own LP (core/isp/sheet_subproblem.h) alive for the whole run.
// Separation rows found later can couple subproblems: attaching such a row merges them into one
// whose LP is rebuilt; every other LP keeps its warm start. The set owns what all LPs share (the
// context: bundle-to-column and row-to-LP-row maps, the deduplicated consistency rows over
// bundles, the LP factory), so it is neither copied nor moved.
#ifndef ISPQ_CORE_ISP_SUBPROBLEM_SET_H_
#define ISPQ_CORE_ISP_SUBPROBLEM_SET_H_

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/flat_lists.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/sheet_lp.h"
#include "core/isp/sheet_subproblem.h"
#include "core/subproblems.h"

namespace ispq {

class SubproblemSet {
 public:
  // Everything referenced must outlive the set. `floors` flags, per bundle, an always-active row
  // x_b >= 0 (core/isp/sheet_subproblem.h); every row already in `rows` joins its subproblem.
  SubproblemSet(const ConsistencyMatrix& consistency, const ArcBundles& bundles,
                const Subproblems& initial, const BundleQuantization& quantization,
                const InequalityRows& rows, std::vector<uint8_t> floors, int num_arcs,
                SheetLpFactory new_lp, bool decompose);
  SubproblemSet(const SubproblemSet&) = delete;
  SubproblemSet& operator=(const SubproblemSet&) = delete;

  SheetSubproblem& Of(BundleId b) { return *subproblems_[subproblem_of_bundle_[b]]; }
  int32_t IdOf(BundleId b) const { return subproblem_of_bundle_[b]; }
  // Ids of the subproblems with a violated active row, ascending.
  std::vector<int32_t> WithViolatedRows() const;
  SheetSubproblem& at(int32_t id) { return *subproblems_[id]; }
  // Subproblems left after merging, and their ids, ascending.
  int count() const;
  std::vector<int32_t> Ids() const;

  // Row r changed activity: refreshes it in its LP and returns true, or returns false if it is
  // in no LP yet (it must be attached).
  bool MarkRowChanged(int32_t r);
  // Adds rows to the LPs of their subproblems, merging the subproblems a row couples.
  void Attach(std::span<const int32_t> new_rows);
  // Adds rows over the bundles of subproblem `id` alone to its LP.
  void AttachTo(int32_t id, std::span<const int32_t> new_rows);
  // From now on the LPs without a root of subproblems of at least `min_bundles` bundles are
  // first solved as flows over these potentials (SheetLpContext::potentials), stopped by
  // `should_stop`.
  void UseFlows(const BundlePotentials* potentials, size_t min_bundles, LpStopCheck should_stop) {
    context_.potentials = potentials;
    context_.flow_min_bundles = min_bundles;
    context_.should_stop = std::move(should_stop);
  }

 private:
  void BuildEqualities(const ConsistencyMatrix& consistency, const ArcBundles& bundles,
                       const Subproblems& initial);
  void Build(const Subproblems& initial, bool decompose);
  // Replaces the subproblems `members` by one holding their bundles, equalities and rows plus
  // `new_rows`.
  void Merge(std::span<const int32_t> members, std::span<const int32_t> new_rows);

  const InequalityRows& rows_;
  SheetLpContext context_;
  FlatLists<LinearTerm> equalities_;                  // consistency rows over bundles, deduplicated
  std::vector<int32_t> equality_initial_subproblem_;  // per equality
  std::vector<std::unique_ptr<SheetSubproblem>> subproblems_;  // null once merged into another
  std::vector<int32_t> subproblem_of_bundle_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SUBPROBLEM_SET_H_
