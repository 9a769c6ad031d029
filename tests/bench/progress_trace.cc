// SPDX-License-Identifier: Apache-2.0
#include "tests/bench/progress_trace.h"

#include <cmath>

namespace ispq::bench {
namespace {

// A change smaller than this (relative) is not a new point.
bool Improves(const std::optional<double>& old_value, double value, bool lower_is_better) {
  if (!old_value.has_value()) return true;
  const double margin = 1e-9 * (1 + std::abs(*old_value));
  return lower_is_better ? value < *old_value - margin : value > *old_value + margin;
}

}  // namespace

void ProgressTrace::OnProgress(const ProgressEvent& event) {
  bool changed = false;
  if (event.separating && Improves(best_, event.objective, true)) {
    best_ = event.objective;
    changed = true;
  }
  if (event.lower_bound.has_value() && Improves(bound_, *event.lower_bound, false)) {
    bound_ = event.lower_bound;
    changed = true;
  }
  if (changed) points_.push_back({event.elapsed_seconds, best_, bound_});
}

void ProgressTrace::WriteHeader(std::ostream& out) {
  out << "model\tlevel\tmethod\tseconds\tobjective\tlower_bound\n";
}

void ProgressTrace::WriteRows(const std::string& model, int level, const std::string& method,
                              std::ostream& out) const {
  for (const TracePoint& p : points_) {
    out << model << "\t" << level << "\t" << method << "\t" << p.seconds << "\t";
    if (p.objective.has_value()) out << *p.objective;
    out << "\t";
    if (p.lower_bound.has_value()) out << *p.lower_bound;
    out << "\n";
  }
}

}  // namespace ispq::bench
