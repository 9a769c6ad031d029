// SPDX-License-Identifier: Apache-2.0
// The inequality rows of the sheet LPs, written over bundles (paper App. A, eqs. 7c and 7d):
// block-extent rows C (and optional per-arc bounds) from the start, then the simple and the
// structural separation rows as the lazy separation search finds them, structural ones in their
// default and failsafe (App. B) forms. Each row reads sum coef * x_b >= rhs (core/README.md,
// section Sheet LPs).
//
// Every row keeps its value at the current quantization, updated as bundles move, so that the
// LP right-hand sides rhs - B q_pre, the violation count reported to observers and the bounds of
// a sheet's multiplicity are all read in O(1) per row. Rows are deduplicated on insertion: the
// search reports the same violation from several starts.
#ifndef ISPQ_CORE_ISP_INEQUALITY_ROWS_H_
#define ISPQ_CORE_ISP_INEQUALITY_ROWS_H_

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/flat_lists.h"

namespace ispq {

enum class RowOrigin : uint8_t {
  kBlockExtent,    // C: a block's extent along one axis is >= 0
  kArcLowerBound,  // C with the per-arc switch: q_a >= bound
  kSimple,         // links and regions do not collapse (proto/README.md, section Separation)
  kStructural,     // a path found by the separation search, default form
  kFailsafe,       // the same path, non-negative failsafe form B+
};

class InequalityRows {
 public:
  explicit InequalityRows(int num_bundles);

  int size() const { return terms_.size(); }
  // Id of a row with exactly these terms and rhs, or kNoId.
  int32_t Find(std::span<const LinearTerm> terms, int64_t rhs) const;
  // Appends a row; `terms` are over bundles, sorted by bundle, with non-zero coefficients.
  // `values` are the current bundle values.
  int32_t Add(std::span<const LinearTerm> terms, int64_t rhs, RowOrigin origin, bool active,
              std::span<const int64_t> values);

  std::span<const LinearTerm> terms(int32_t r) const { return terms_[r]; }
  int64_t rhs(int32_t r) const { return rhs_[r]; }
  RowOrigin origin(int32_t r) const { return origin_[r]; }
  int64_t value(int32_t r) const { return value_[r]; }
  // value - rhs: how much the row may lose before it is violated (negative when violated).
  int64_t slack(int32_t r) const { return value_[r] - rhs_[r]; }
  bool violated(int32_t r) const { return value_[r] < rhs_[r]; }

  // Inactive rows stay in the store (and in the LPs, with a vacuous bound) but do not count.
  bool active(int32_t r) const { return active_[r] != 0; }
  void SetActive(int32_t r, bool active);
  int64_t num_violated_active() const { return num_violated_active_; }

  struct Incidence {
    int32_t row;
    int32_t coef;
  };
  std::span<const Incidence> rows_of_bundle(BundleId b) const { return rows_of_bundle_[b]; }

  // Bundle b moved by delta: updates the values of its rows.
  void OnBundleMoved(BundleId b, int64_t delta);

 private:
  static uint64_t Hash(std::span<const LinearTerm> terms, int64_t rhs);
  void CountViolation(int32_t r, int sign);

  FlatLists<LinearTerm> terms_;
  std::vector<int64_t> rhs_;
  std::vector<RowOrigin> origin_;
  std::vector<int64_t> value_;
  std::vector<uint8_t> active_;
  std::vector<std::vector<Incidence>> rows_of_bundle_;
  int64_t num_violated_active_ = 0;
  // Hash of (terms, rhs) -> first row with that hash; further ones chained through next_same_.
  std::unordered_map<uint64_t, int32_t> first_with_hash_;
  std::vector<int32_t> next_same_hash_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_INEQUALITY_ROWS_H_
