// SPDX-License-Identifier: Apache-2.0
#include "core/bundle_row_pair.h"

namespace ispq {

BundleRowPair ToBundleRowPair(const ArcBundles& bundles, const SeparationRow& default_row,
                              const SeparationRow& failsafe_row) {
  BundleRowPair pair;
  pair.failsafe_terms = bundles.ToBundleTerms(failsafe_row.terms);
  pair.failsafe_rhs = failsafe_row.rhs;
  pair.default_terms = bundles.ToBundleTerms(default_row.terms);
  pair.default_rhs = default_row.rhs;
  if (pair.default_terms.empty()) {
    pair.default_terms = pair.failsafe_terms;
    pair.default_rhs = pair.failsafe_rhs;
  }
  return pair;
}

}  // namespace ispq
