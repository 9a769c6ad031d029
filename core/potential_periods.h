// SPDX-License-Identifier: Apache-2.0
// The periods of a part with handles, over its node potentials (core/bundle_potentials.h).
//
// On a part with global frames, a potential difference is always a consistent q, but where the
// part has handles not every consistent q is one: around a through hole, the two sides of the
// hole may differ in length. Take a spanning forest of the potentials with bundles as edges; every
// consistent q minus the potential differences that match it on the forest is a consistent q that
// is zero on the forest, so the consistency rows, restricted to the bundles off the forest, say
// all there is. Resolving them (a row with one term left fixes that term's class at zero; a row
// with two terms of equal magnitude makes their classes equal or opposite; the rows still open
// around each handle, 3.5k at 300k arcs of the single family and 12k at 10^6, are eliminated,
// shortest first, each making a class an integer combination of others) leaves free classes: the
// periods. Then every consistent q is U[head] - U[tail] plus an
// integer combination of the periods P per bundle, for potentials U and integer periods P, and
// every such q is consistent.
//
// Where an open row has no term of coefficient +-1 left to eliminate, or coefficients grow large,
// there is no answer (the LP keeps such parts).
#ifndef ISPQ_CORE_POTENTIAL_PERIODS_H_
#define ISPQ_CORE_POTENTIAL_PERIODS_H_

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/flat_lists.h"
#include "core/linear_terms.h"

namespace ispq {

struct PotentialPeriods {
  int32_t num_periods = 0;
  // Per bundle: the periods its q carries (var: the period, coef: how many times), or none.
  FlatLists<LinearTerm> terms;
};

// `tail`, `head`: per bundle, its potentials (0..num_potentials-1).
std::optional<PotentialPeriods> FindPotentialPeriods(int32_t num_potentials,
                                                     std::span<const int32_t> tail,
                                                     std::span<const int32_t> head,
                                                     const ConsistencyMatrix& consistency,
                                                     const ArcBundles& bundles);

}  // namespace ispq

#endif  // ISPQ_CORE_POTENTIAL_PERIODS_H_
