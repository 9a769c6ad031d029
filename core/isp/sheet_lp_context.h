// SPDX-License-Identifier: Apache-2.0
// The state all subproblem LPs of one quantization run share (core/isp/sheet_subproblem.h): the
// quantization, the inequality rows and the consistency rows they are written over, the LP
// factory, and the maps from bundles and rows to their places in their subproblem's LP. The
// subproblem set (core/isp/subproblem_set.h) owns it.
#ifndef ISPQ_CORE_ISP_SHEET_LP_CONTEXT_H_
#define ISPQ_CORE_ISP_SHEET_LP_CONTEXT_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "core/bundle_potentials.h"
#include "core/consistency_matrix.h"
#include "core/flat_lists.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/sheet_lp.h"

namespace ispq {

struct SheetLpContext {
  const BundleQuantization* quantization;
  const InequalityRows* rows;
  const FlatLists<LinearTerm>* equalities;  // consistency rows over bundles
  double num_arcs;                          // |A| in the weights of eq. 4
  std::function<std::unique_ptr<SheetLp>(int num_columns)> new_lp;
  // Per bundle: its column pair index in its current subproblem. Per inequality row: its row
  // index in its subproblem's LP. Each bundle and row belongs to exactly one subproblem.
  std::vector<int32_t> local_index_of_bundle;
  std::vector<int32_t> lp_row_of_row;
  // Per bundle: whether an always-active row x_b >= 0 exists (a block extent or arc bound over
  // this bundle alone). A request that would take such a bundle below 0 is infeasible without
  // asking the solver (common: deflating a root that is already 0).
  std::vector<uint8_t> has_floor;
  // Whether requests are first put to bound propagation (core/isp/sheet_infeasibility.h), which
  // answers most infeasible ones without the solver; off only to compare against the solver.
  bool refute_by_propagation = true;
  // Upper bound of every free column for LPs that want one (core/isp/sheet_subproblem.h). Real
  // sheets move a bundle by a few units.
  double column_cap = 1024;
  // Where every consistent q is a potential difference (core/bundle_potentials.h), the LPs
  // without a root of subproblems of at least flow_min_bundles bundles are first solved as
  // min-cost flows (core/isp/sheet_network.h); null: by the LP alone. The flows ask
  // `should_stop` as the LPs ask theirs.
  const BundlePotentials* potentials = nullptr;
  size_t flow_min_bundles = 0;
  LpStopCheck should_stop;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_LP_CONTEXT_H_
