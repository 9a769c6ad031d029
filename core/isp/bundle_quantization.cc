// SPDX-License-Identifier: Apache-2.0
#include "core/isp/bundle_quantization.h"

#include "core/invariant.h"

namespace ispq {

BundleQuantization::BundleQuantization(const TMesh& mesh, const ArcBundles& bundles, double scaling)
    : bundle_of_arc_(bundles.bundle_of_arc().begin(), bundles.bundle_of_arc().end()),
      arc_target_(mesh.num_arcs()),
      target_sum_(bundles.num_bundles(), 0.0),
      value_(bundles.num_bundles(), 0) {
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) arc_target_[a] = scaling * mesh.arc_length(a);
  std::vector<double> list;
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    list.clear();
    for (ArcId a : bundles.arcs(b)) {
      list.push_back(arc_target_[a]);
      target_sum_[b] += arc_target_[a];
    }
    targets_.Append(list);
  }
  objective_ = ExactObjective();
}

StepQuadratic BundleQuantization::Quadratic(const IntegerSheet& sheet) const {
  // Bundle part: m (x + t d)^2 - 2 S (x + t d) + const, so the change is
  // m d^2 t^2 + 2 d (m x - S) t.
  StepQuadratic f;
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    const BundleId b = sheet.bundles[i];
    const double d = static_cast<double>(sheet.deltas[i]);
    const double m = static_cast<double>(targets_[b].size());
    f.a += m * d * d;
    f.b += 2 * d * (m * static_cast<double>(value_[b]) - target_sum_[b]);
  }
  return f;
}

void BundleQuantization::Apply(const IntegerSheet& sheet, int64_t t) {
  ISPQ_INVARIANT(sheet.bundles.size() == sheet.deltas.size(), "one delta per bundle of a sheet");
  objective_ += Quadratic(sheet).At(t);
  for (size_t i = 0; i < sheet.bundles.size(); ++i) value_[sheet.bundles[i]] += t * sheet.deltas[i];
}

void BundleQuantization::SetValues(std::span<const int64_t> bundle_values) {
  ISPQ_INVARIANT(bundle_values.size() == value_.size(), "one value per bundle");
  value_.assign(bundle_values.begin(), bundle_values.end());
  objective_ = ExactObjective();
}

std::vector<int64_t> BundleQuantization::ArcValues() const {
  std::vector<int64_t> q;
  ArcValues(&q);
  return q;
}

void BundleQuantization::ArcValues(std::vector<int64_t>* q) const {
  q->resize(arc_target_.size());
  for (size_t a = 0; a < arc_target_.size(); ++a) (*q)[a] = value_[bundle_of_arc_[a]];
}

double BundleQuantization::ExactObjective() const {
  double sum = 0;
  for (size_t a = 0; a < arc_target_.size(); ++a) {
    const double d = static_cast<double>(value_[bundle_of_arc_[a]]) - arc_target_[a];
    sum += d * d;
  }
  return sum;
}

}  // namespace ispq
