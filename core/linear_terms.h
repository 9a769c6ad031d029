// SPDX-License-Identifier: Apache-2.0
// Terms coef * x_var of a linear row, and the one routine that brings a row to its canonical
// form: every variable once, no zero coefficient. Rows are put together from pieces that may
// name a variable twice (a separation row's two paths share arcs, two arcs of a row may lie in
// one bundle, a caller's row may repeat a column), and both the LU factorization and row
// deduplication want each variable once.
#ifndef ISPQ_CORE_LINEAR_TERMS_H_
#define ISPQ_CORE_LINEAR_TERMS_H_

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace ispq {

struct LinearTerm {
  int32_t var;  // an arc id, or a bundle id once rows are expressed on bundles
  int32_t coef;
  friend bool operator==(const LinearTerm&, const LinearTerm&) = default;
};

// Sums the coefficients of the terms from `begin` on that share a variable into the first of
// them, and removes the terms whose sum is zero. The kept terms stay in the order of their
// variables' first appearance and each sum adds in order of appearance, so the result does not
// depend on how the routine works inside (the LP back ends see the same row either way). `Term`
// is any struct with members `var` and `coef`.
template <typename Term>
void MergeRepeatedTerms(std::vector<Term>& terms, size_t begin = 0) {
  const size_t n = terms.size() - begin;
  // Most rows have a handful of terms: a scan of the kept ones is cheaper than sorting.
  constexpr size_t kScanLimit = 16;
  size_t kept = begin;
  if (n == 0) return;
  if (n <= kScanLimit) {
    for (size_t t = begin; t < terms.size(); ++t) {
      size_t at = begin;
      while (at < kept && terms[at].var != terms[t].var) ++at;
      if (at == kept) {
        terms[kept++] = terms[t];
      } else {
        terms[at].coef += terms[t].coef;
      }
    }
  } else {
    // Long rows (failsafe rows of large meshes): find each variable's first term by sorting
    // positions, stably, by variable; later terms add into it and are marked gone.
    std::vector<size_t> order(n);
    std::iota(order.begin(), order.end(), begin);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t x, size_t y) { return terms[x].var < terms[y].var; });
    std::vector<uint8_t> merged_away(n, 0);
    size_t first = order[0];  // the first appearance of the current run's variable
    for (size_t i = 1; i < n; ++i) {
      if (terms[order[i]].var != terms[first].var) {
        first = order[i];
        continue;
      }
      terms[first].coef += terms[order[i]].coef;
      merged_away[order[i] - begin] = 1;
    }
    for (size_t t = begin; t < terms.size(); ++t) {
      if (!merged_away[t - begin]) terms[kept++] = terms[t];
    }
  }
  terms.resize(kept);
  size_t nonzero = begin;
  for (size_t t = begin; t < kept; ++t) {
    if (terms[t].coef != 0) terms[nonzero++] = terms[t];
  }
  terms.resize(nonzero);
}

}  // namespace ispq

#endif  // ISPQ_CORE_LINEAR_TERMS_H_
