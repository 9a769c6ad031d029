// SPDX-License-Identifier: Apache-2.0
// The objective d(q) = sum_a (q_a - s * l_a)^2 split over arc bundles (core/arc_bundles.h), and
// its piecewise-linear form on the integers, which is what makes the problem a MILP.
//
// A bundle b of m arcs with scaled targets t_a at value x contributes f_b(x) = sum (x - t_a)^2,
// a convex parabola. On the integers f_b equals its linear interpolation through consecutive
// integers, i.e. the maximum of the secants between k and k + 1: every such secant lies below
// f_b at every integer. So min sum_b z_b with z_b >= each secant is exact on integer x, and its
// LP relaxation is much tighter than the continuous QP (which may sit between two integers).
//
// Only finitely many secants are needed: if some q with d(q) <= U is sought, each bundle must
// satisfy f_b(x_b) <= f_b(best_b) + (U - sum_c f_c(best_c)) where best_c is c's best integer, so
// x_b lies in an integer window around its target and the secants inside it are exact there.
#ifndef ISPQ_CORE_EXACT_BUNDLE_OBJECTIVE_H_
#define ISPQ_CORE_EXACT_BUNDLE_OBJECTIVE_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/arc_bundles.h"
#include "core/flat_lists.h"
#include "core/tmesh.h"

namespace ispq {

// The integers lo..hi.
struct IntegerWindow {
  int64_t lo = 0;
  int64_t hi = 0;
};

// The secant of f_b between k and k + 1: value + slope * (x - k).
struct Secant {
  int64_t k;
  double value;  // f_b(k)
  double slope;  // f_b(k + 1) - f_b(k)
};

class BundleObjectives {
 public:
  BundleObjectives(const TMesh& mesh, const ArcBundles& bundles, double scaling);

  int num_bundles() const { return targets_.size(); }
  // f_b(x), summed arc by arc (exact up to rounding, whatever x).
  double Value(BundleId b, int64_t x) const;
  // The integer minimizing f_b (the rounded mean target).
  int64_t BestInteger(BundleId b) const { return best_[b]; }
  // sum_b f_b(BestInteger(b)): no q has a smaller objective.
  double MinimumSum() const { return minimum_sum_; }
  // The integers x with f_b(x) <= f_b(BestInteger(b)) + slack (slack >= 0), widened by a
  // rounding margin so that it never misses one.
  IntegerWindow Window(BundleId b, double slack) const;
  Secant SecantAt(BundleId b, int64_t k) const;

  // d(q) for q per bundle.
  double Objective(std::span<const int64_t> bundle_values) const;

 private:
  FlatLists<double> targets_;  // scaled targets of each bundle's arcs
  std::vector<double> mean_;
  std::vector<int64_t> best_;
  double minimum_sum_ = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_BUNDLE_OBJECTIVE_H_
