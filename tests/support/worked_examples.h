// SPDX-License-Identifier: Apache-2.0
// The worked examples that tests check by hand, as grid-builder inputs: the 2D separation examples
// A, B and C (core/README.md, section Cases with known answers) and the ISP paper's half-integral
// sheet (Figs. 6, 7). They live apart from the builder (tests/support/grid_tmesh_builder.h), which
// knows nothing of any particular mesh; the separation and sheet tests build them from here.
#ifndef ISPQ_TESTS_SUPPORT_WORKED_EXAMPLES_H_
#define ISPQ_TESTS_SUPPORT_WORKED_EXAMPLES_H_

#include <utility>
#include <vector>

#include "tests/support/grid_tmesh_builder.h"

namespace ispq::testing {

// The 2D worked examples A, B and C of core/README.md, section Cases with known answers, as
// layouts with their target lengths. Points are grid indices, not target coordinates.
//
// Example A: u indices 0..3 at target u 0, 2.5, 2.5 + g1, 3.5 + g1; v indices 0..3 at 0, 0.5,
// 1, 2. F = (1, 2) is the feature node, I = (1, 1), K = (2, 1), J = (2, 0), x0 = (0, 0).
// `g1_length` is the length of arc I-K: 0.5 in the example, 3 in test T11.
GridLayout2D SeparationExampleA(double g1_length = 0.5);
// Example B: u indices at target u 0, 3, t_u, 5, 6 in increasing order, merged where equal; v
// indices 0..4 at -1..3. With f, t, k the u indices of 3, t_u and 5: F = (f, 3), I = (f, 2),
// K = (k, 2), Q = (k, 1), T = (t, 1). t_u is the target u of T (0 < t_u < 5): 3.2 in the
// example, 3, 2.5 and 3.5 in test T12. Its feature_nodes are {F, T}.
GridLayout2D SeparationExampleB(double t_u = 3.2);
// Example C, no features: u and v indices equal the target coordinates. M = (0, 0), N = (1, 0),
// O = (3, 0), H = (1, 1), K = (3, 1), E = (1, 2), F = (2, 2), C = (2, 3), I = (3, 3); the slot
// [1, 3] x [1, 2] and the gap [2, 3] x [2, 3] are empty.
GridLayout2D SeparationExampleC();

// A T-mesh on which the sheet LP of the ISP paper (eq. 2) has only half-integral optima: the
// "U-turn of T-junctions" of the paper's Figs. 6 and 7. Seven blocks, u in [0, 2], wind around
// an empty tunnel [0, 2] x [1, 2] x [1, 2] along u; half of them span only u in [0, 1] or
// [1, 2], so a sheet through the u-half [0, 1] comes back round the tunnel in the other half.
// Forcing the root arc (u-length 2) to 1, `min sum_a q_a` subject to patch consistency,
// q >= 0, q_root >= 1 has the optimum 11.5 (checked with CLP; also fractional for 198 of 200
// random positive weight vectors): q_root = 1 and 1/2 on the 21 `half_arcs`. No integral
// solution reaches 11.5; doubling gives an integer sheet (lcd 2).
//
// Fig. 6 itself is a 2D layout whose U-turn needs a rotational transition (a cone
// singularity), which one global grid cannot express: every planar axis-aligned layout, and its
// extrusion, has a totally unimodular consistency matrix per axis and integral LP vertices.
struct HalfIntegerSheetExample {
  GridTMeshSpec spec;
  std::pair<GridPoint, GridPoint> root;
  std::vector<std::pair<GridPoint, GridPoint>> half_arcs;
};
HalfIntegerSheetExample MakeHalfIntegerSheetExample();

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_WORKED_EXAMPLES_H_
