// SPDX-License-Identifier: Apache-2.0
// The quantization as the ISP driver sees it: one integer per arc bundle (core/arc_bundles.h),
// since every arc of a bundle always has the same length, with the objective
// d(q) = sum_a (q_a - s * l_a)^2 over ALL arcs kept up to date incrementally.
//
// Per bundle it stores the arc count m, the sum of scaled targets S and their squares, so the
// bundle's part of the objective at value x is m x^2 - 2 S x + sum t^2 and any move costs O(1).
#ifndef ISPQ_CORE_ISP_BUNDLE_QUANTIZATION_H_
#define ISPQ_CORE_ISP_BUNDLE_QUANTIZATION_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/arc_bundles.h"
#include "core/flat_lists.h"
#include "core/isp/integer_sheet.h"
#include "core/tmesh.h"

namespace ispq {

// Coefficients of d(q + t * sheet) - d(q) = a t^2 + b t.
struct StepQuadratic {
  double a = 0;
  double b = 0;
  double At(int64_t t) const {
    const double td = static_cast<double>(t);
    return a * td * td + b * td;
  }
};

class BundleQuantization {
 public:
  // All values start at 0 (the paper's trivially consistent q^0).
  BundleQuantization(const TMesh& mesh, const ArcBundles& bundles, double scaling);

  int num_bundles() const { return static_cast<int>(value_.size()); }
  int64_t value(BundleId b) const { return value_[b]; }
  std::span<const int64_t> values() const { return value_; }
  int arc_count(BundleId b) const { return static_cast<int>(targets_[b].size()); }
  // Scaled targets s * l_a of the bundle's arcs.
  std::span<const double> targets(BundleId b) const { return targets_[b]; }
  // Sum of the scaled targets of the bundle's arcs.
  double target_sum(BundleId b) const { return target_sum_[b]; }
  // Mean target minus value: where the bundle alone would like to move, and how far.
  double mean_deviation(BundleId b) const {
    return target_sum_[b] / static_cast<double>(targets_[b].size()) -
           static_cast<double>(value_[b]);
  }

  double objective() const { return objective_; }
  // A step gains something only below minus this: rounding noise of the objective's sums.
  double GainTolerance() const { return 1e-9 * (1.0 + std::abs(objective_)); }
  StepQuadratic Quadratic(const IntegerSheet& sheet) const;
  // Objective change if bundle b alone moved by delta.
  double MoveChange(BundleId b, int64_t delta) const {
    const double d = static_cast<double>(delta);
    const double m = static_cast<double>(targets_[b].size());
    return m * d * d + 2 * d * (m * static_cast<double>(value_[b]) - target_sum_[b]);
  }
  void Apply(const IntegerSheet& sheet, int64_t t);
  void SetValues(std::span<const int64_t> bundle_values);

  // q per arc.
  std::vector<int64_t> ArcValues() const;
  void ArcValues(std::vector<int64_t>* q) const;
  // d(q) recomputed from scratch over all arcs (the incremental value drifts by rounding only).
  double ExactObjective() const;

 private:
  std::vector<BundleId> bundle_of_arc_;
  std::vector<double> arc_target_;
  FlatLists<double> targets_;
  std::vector<double> target_sum_;
  std::vector<int64_t> value_;
  double objective_ = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_BUNDLE_QUANTIZATION_H_
