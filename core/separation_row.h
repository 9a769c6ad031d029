// SPDX-License-Identifier: Apache-2.0
// A linear inequality over arc lengths, sum_i coef_i * q_{arc_i} >= rhs: the form of every
// separation constraint (paper eq. 1c) and of the simple rows (links, regions, block extents);
// core/README.md, section The problem.
#ifndef ISPQ_CORE_SEPARATION_ROW_H_
#define ISPQ_CORE_SEPARATION_ROW_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/linear_terms.h"

namespace ispq {

struct SeparationRow {
  std::vector<LinearTerm> terms;  // var = arc id; each arc at most once
  int64_t rhs = 1;

  int64_t Evaluate(std::span<const int64_t> q) const {
    int64_t sum = 0;
    for (const LinearTerm& t : terms) sum += t.coef * q[t.var];
    return sum;
  }
  bool IsSatisfiedBy(std::span<const int64_t> q) const { return Evaluate(q) >= rhs; }
  friend bool operator==(const SeparationRow&, const SeparationRow&) = default;
};

}  // namespace ispq

#endif  // ISPQ_CORE_SEPARATION_ROW_H_
