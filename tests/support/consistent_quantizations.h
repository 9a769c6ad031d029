// SPDX-License-Identifier: Apache-2.0
// Consistent integer quantizations of real T-meshes, built without the quantizer.
//
// Tests of the separation search and of the validator need inputs that satisfy every
// consistency row (opposite patch sides have equal sums), which rounding target lengths almost
// never gives on a T-mesh. This solves the consistency system exactly once per mesh (sparse
// fraction-free elimination over the integers): the arcs split into "free" arcs, whose values can
// be chosen at will, and the others, which those values determine. Choosing the free values as
// rounded scaled target lengths gives a q near the targets; choosing them sparse gives many zero
// arcs and hence many separation violations.
#ifndef ISPQ_TESTS_SUPPORT_CONSISTENT_QUANTIZATIONS_H_
#define ISPQ_TESTS_SUPPORT_CONSISTENT_QUANTIZATIONS_H_

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/tmesh.h"

namespace ispq::testing {

class ConsistentQuantizations {
 public:
  // Aborts the test binary if the elimination overflows int64 (it does not on the real data).
  explicit ConsistentQuantizations(const TMesh& mesh);

  // The arcs whose values parametrize all consistent q, ascending.
  std::span<const ArcId> free_arcs() const { return free_arcs_; }

  // The consistent q that equals multiplier * free_values on the free arcs (free_values in the
  // order of free_arcs()), where multiplier is the smallest positive integer that makes every
  // other arc integral for every choice of free values.
  std::vector<int64_t> Extend(std::span<const int64_t> free_values) const;
  int64_t multiplier() const { return multiplier_; }

  // Extend() of round(scale * target length) on the free arcs.
  std::vector<int64_t> NearTargets(double scale) const;

 private:
  int num_arcs_ = 0;
  std::vector<ArcId> free_arcs_;
  // Each determined arc: pivot * q_arc + sum coef * q_free = 0 (free arcs as column ids).
  struct Determined {
    ArcId arc;
    int64_t pivot;
    std::vector<std::pair<ArcId, int64_t>> free_terms;
  };
  std::vector<Determined> determined_;
  int64_t multiplier_ = 1;
  std::vector<double> lengths_;
};

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_CONSISTENT_QUANTIZATIONS_H_
