// SPDX-License-Identifier: Apache-2.0
#include "core/exact/window_slacks.h"

#include <algorithm>

#include "core/disjoint_sets.h"

namespace ispq {
namespace {

int64_t RowValue(std::span<const LinearTerm> terms, std::span<const int64_t> x) {
  int64_t sum = 0;
  for (const LinearTerm& t : terms) sum += t.coef * x[t.var];
  return sum;
}

// Components of the bundles under every row, and whether x satisfies all rows of each.
struct Components {
  std::vector<int32_t> of_bundle;
  std::vector<uint8_t> satisfied;  // per component representative
};

Components FindComponents(int num_bundles, const QuantizationConstraints& constraints,
                          std::span<const int64_t> x) {
  DisjointSets sets(num_bundles);
  const auto join = [&sets](std::span<const LinearTerm> terms) {
    for (const LinearTerm& t : terms) sets.Join(terms[0].var, t.var);
  };
  for (int i = 0; i < constraints.num_equalities(); ++i) join(constraints.equality(i));
  for (int i = 0; i < constraints.num_inequalities(); ++i) join(constraints.inequality(i));
  Components components{std::vector<int32_t>(num_bundles), std::vector<uint8_t>(num_bundles, 1)};
  for (BundleId b = 0; b < num_bundles; ++b) components.of_bundle[b] = sets.Find(b);
  for (int i = 0; i < constraints.num_equalities(); ++i) {
    const std::span<const LinearTerm> row = constraints.equality(i);
    if (RowValue(row, x) != 0) components.satisfied[components.of_bundle[row[0].var]] = 0;
  }
  for (int i = 0; i < constraints.num_inequalities(); ++i) {
    const std::span<const LinearTerm> row = constraints.inequality(i);
    if (RowValue(row, x) < constraints.rhs(i)) {
      components.satisfied[components.of_bundle[row[0].var]] = 0;
    }
  }
  return components;
}

}  // namespace

std::vector<double> WindowSlacks(const BundleObjectives& objectives,
                                 const QuantizationConstraints& constraints,
                                 std::span<const int64_t> x) {
  const int n = objectives.num_bundles();
  const Components components = FindComponents(n, constraints, x);
  // Per component: the objective of x on it minus its minimum.
  std::vector<double> excess(n, 0.0);
  double total = 0;
  for (BundleId b = 0; b < n; ++b) {
    const double e = objectives.Value(b, x[b]) - objectives.Value(b, objectives.BestInteger(b));
    excess[components.of_bundle[b]] += e;
    total += e;
  }
  std::vector<double> slacks(n);
  for (BundleId b = 0; b < n; ++b) {
    const int32_t c = components.of_bundle[b];
    slacks[b] = std::max(0.0, components.satisfied[c] ? excess[c] : total);
  }
  return slacks;
}

}  // namespace ispq
