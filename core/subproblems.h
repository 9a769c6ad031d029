// SPDX-License-Identifier: Apache-2.0
// Independent subproblems (paper section 4.4; core/README.md, section Bundles and subproblems):
// connected components of the bundles under the model's own constraints, the consistency rows and
// the block-extent rows. A sheet rooted in one component never changes another, so each component
// gets its own small LP. Separation rows found later can join components; core/isp/subproblem_set.h
// merges them then.
#ifndef ISPQ_CORE_SUBPROBLEMS_H_
#define ISPQ_CORE_SUBPROBLEMS_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/tmesh.h"

namespace ispq {

class Subproblems {
 public:
  Subproblems(const TMesh& mesh, const ConsistencyMatrix& consistency, const ArcBundles& bundles);

  int num_subproblems() const { return static_cast<int>(bundles_of_.size()); }
  int32_t subproblem_of(BundleId b) const { return subproblem_of_[b]; }
  // Bundles of a subproblem, ascending.
  const std::vector<BundleId>& bundles(int32_t s) const { return bundles_of_[s]; }

 private:
  std::vector<int32_t> subproblem_of_;
  std::vector<std::vector<BundleId>> bundles_of_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_SUBPROBLEMS_H_
