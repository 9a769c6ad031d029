// SPDX-License-Identifier: Apache-2.0
#include "tests/support/worked_examples.h"

#include <algorithm>

namespace ispq::testing {

GridLayout2D SeparationExampleA(double g1_length) {
  GridLayout2D layout;
  layout.name = "separation_example_a";
  // Rows from the bottom: low (Z0, Z1), mid (Y0, Y1), top (X0, X1).
  layout.blocks = {{{0, 0}, {2, 1}}, {{2, 0}, {3, 1}}, {{0, 1}, {1, 2}},
                   {{1, 1}, {3, 2}}, {{0, 2}, {1, 3}}, {{1, 2}, {3, 3}}};
  layout.spacing = {{{2.5, g1_length, 1.0}, {0.5, 0.5, 1.0}}};
  layout.feature_nodes = {{1, 2}};
  return layout;
}

GridLayout2D SeparationExampleB(double t_u) {
  std::vector<double> u = {0, 3, t_u, 5, 6};
  std::sort(u.begin(), u.end());
  u.erase(std::unique(u.begin(), u.end()), u.end());
  auto index = [&](double x) {
    return static_cast<int>(std::find(u.begin(), u.end(), x) - u.begin());
  };
  const int f = index(3), t = index(t_u), k = index(5), y = index(6);
  GridLayout2D layout;
  layout.name = "separation_example_b";
  // Rows from the bottom: B1 B2, L1 L2, M1 M2, U1 U2.
  layout.blocks = {{{0, 0}, {t, 1}}, {{t, 0}, {y, 1}}, {{0, 1}, {k, 2}}, {{k, 1}, {y, 2}},
                   {{0, 2}, {f, 3}}, {{f, 2}, {y, 3}}, {{0, 3}, {f, 4}}, {{f, 3}, {y, 4}}};
  for (size_t i = 0; i + 1 < u.size(); ++i) layout.spacing[0].push_back(u[i + 1] - u[i]);
  layout.feature_nodes = {{f, 3}, {t, 1}};
  return layout;
}

GridLayout2D SeparationExampleC() {
  GridLayout2D layout;
  layout.name = "separation_example_c";
  // Base B0 B1 B2, left prong P0 P1 with the overhang P2, right prong P4.
  layout.blocks = {{{0, 0}, {1, 1}}, {{1, 0}, {3, 1}}, {{3, 0}, {4, 1}}, {{0, 1}, {1, 2}},
                   {{0, 2}, {1, 3}}, {{1, 2}, {2, 3}}, {{3, 1}, {4, 3}}};
  return layout;
}

HalfIntegerSheetExample MakeHalfIntegerSheetExample() {
  HalfIntegerSheetExample example;
  example.spec.name = "half_integer_sheet";
  // Bottom bar, two middle blocks across the full width and one in the u-half [1, 2], the top
  // bar in the u-half [1, 2] and two top blocks; found by a randomized search and minimized.
  example.spec.blocks = {{{0, 0, 0}, {1, 3, 1}}, {{0, 0, 1}, {2, 1, 2}}, {{0, 2, 1}, {2, 3, 2}},
                         {{1, 3, 1}, {2, 4, 2}}, {{1, 0, 2}, {2, 3, 3}}, {{0, 2, 2}, {1, 3, 3}},
                         {{0, 3, 2}, {2, 4, 3}}};
  example.root = {{0, 4, 3}, {2, 4, 3}};
  example.half_arcs = {{{0, 0, 0}, {1, 0, 0}}, {{0, 3, 0}, {1, 3, 0}}, {{0, 0, 1}, {1, 0, 1}},
                       {{0, 1, 1}, {1, 1, 1}}, {{0, 2, 1}, {1, 2, 1}}, {{1, 2, 1}, {2, 2, 1}},
                       {{0, 3, 1}, {1, 3, 1}}, {{1, 3, 1}, {2, 3, 1}}, {{1, 4, 1}, {2, 4, 1}},
                       {{1, 0, 2}, {2, 0, 2}}, {{1, 1, 2}, {2, 1, 2}}, {{0, 2, 2}, {1, 2, 2}},
                       {{1, 2, 2}, {2, 2, 2}}, {{0, 3, 2}, {1, 3, 2}}, {{1, 3, 2}, {2, 3, 2}},
                       {{0, 4, 2}, {1, 4, 2}}, {{1, 4, 2}, {2, 4, 2}}, {{1, 0, 3}, {2, 0, 3}},
                       {{0, 2, 3}, {1, 2, 3}}, {{0, 3, 3}, {1, 3, 3}}, {{1, 3, 3}, {2, 3, 3}}};
  return example;
}

}  // namespace ispq::testing
