// SPDX-License-Identifier: Apache-2.0
// Arc bundles: arcs forced to equal length by consistency alone (paper section 4.4;
// core/README.md, section Bundles and subproblems).
//
// When both sides of a patch along one axis consist of a single arc, the consistency row says
// q_a = q_b. Merging such arcs transitively gives bundles; the quantizer then works with one
// variable per bundle and drops the rows that became trivial.
#ifndef ISPQ_CORE_ARC_BUNDLES_H_
#define ISPQ_CORE_ARC_BUNDLES_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/consistency_matrix.h"
#include "core/flat_lists.h"
#include "core/tmesh.h"

namespace ispq {

using BundleId = int32_t;

class ArcBundles {
 public:
  ArcBundles(const TMesh& mesh, const ConsistencyMatrix& consistency);

  int num_bundles() const { return arcs_.size(); }
  BundleId bundle_of(ArcId a) const { return bundle_of_arc_[a]; }
  std::span<const BundleId> bundle_of_arc() const { return bundle_of_arc_; }
  // Arcs of a bundle, ascending. Bundles are numbered by their smallest arc.
  std::span<const ArcId> arcs(BundleId b) const { return arcs_[b]; }

  // q per arc from one value per bundle.
  std::vector<int64_t> ArcValues(std::span<const int64_t> bundle_values) const;

  // A row over arcs rewritten over bundles (coefficients of a bundle's arcs added up, zero
  // coefficients dropped), sorted by bundle id.
  std::vector<LinearTerm> ToBundleTerms(std::span<const LinearTerm> arc_terms) const;
  // And back: each bundle written as its smallest arc (how results name a row's bundles).
  std::vector<LinearTerm> ToArcTerms(std::span<const LinearTerm> bundle_terms) const;

 private:
  std::vector<BundleId> bundle_of_arc_;
  FlatLists<ArcId> arcs_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ARC_BUNDLES_H_
