// SPDX-License-Identifier: Apache-2.0
// The two rows of a path the separation search found (core/separation_search.h), its default
// form and its failsafe twin B+ (paper App. B), written over bundles (core/arc_bundles.h): the
// form in which both ISP (core/isp/separation_rows.h) and exact mode
// (core/exact/quantization_constraints.h) add them to their problem, by the same rule.
#ifndef ISPQ_CORE_BUNDLE_ROW_PAIR_H_
#define ISPQ_CORE_BUNDLE_ROW_PAIR_H_

#include <cstdint>
#include <vector>

#include "core/arc_bundles.h"
#include "core/linear_terms.h"
#include "core/separation_row.h"

namespace ispq {

struct BundleRowPair {
  std::vector<LinearTerm> default_terms;
  int64_t default_rhs = 0;
  std::vector<LinearTerm> failsafe_terms;
  int64_t failsafe_rhs = 0;
};

// Both rows over bundles. A default row whose mixed-sign terms cancel within bundles (empty once
// bundled: 0 >= rhs > 0) can never hold; its failsafe twin, whose terms are all positive and so
// never cancel, stands in for it.
BundleRowPair ToBundleRowPair(const ArcBundles& bundles, const SeparationRow& default_row,
                              const SeparationRow& failsafe_row);

}  // namespace ispq

#endif  // ISPQ_CORE_BUNDLE_ROW_PAIR_H_
