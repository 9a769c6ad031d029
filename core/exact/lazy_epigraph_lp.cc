// SPDX-License-Identifier: Apache-2.0
#include "core/exact/lazy_epigraph_lp.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "core/exact/quantization_milp.h"
#include "core/isp/sheet_lp.h"
#include "core/isp/sparse_dual_simplex.h"

namespace ispq {
namespace {

// Rounds of "solve, add the violated secants" before giving up: on the shared meshes 494 of 496
// runs needed one, the others two; a model that needs many more is left to the full model.
constexpr int kMaxRounds = 64;

// A bundle needs an epigraph column when its window holds three integers or more (with one or two
// its objective is constant or linear there, as in core/exact/quantization_milp.h).
bool NeedsEpigraph(const IntegerWindow& window) { return window.hi - window.lo >= 2; }

class LazyEpigraphLp {
 public:
  LazyEpigraphLp(const BundleObjectives& objectives, std::span<const IntegerWindow> windows);

  void AddRows(const QuantizationConstraints& constraints);
  // The secants on both sides of each bundle's value x_b.
  void AddSecantsAround(std::span<const int64_t> x);
  // The secants the last solution violates; false if it violates none not already in the model.
  bool AddViolatedSecants();
  SparseDualSimplex::Status Solve();
  // The last solution's objective, constants included.
  double Objective() const;

 private:
  // Queues z_b >= f_b(k) + slope * (x_b - k) unless present or outside the window.
  void AddSecant(BundleId b, int64_t k);
  void AddBundleColumns(BundleId b);

  const BundleObjectives& objectives_;
  std::span<const IntegerWindow> windows_;
  std::vector<int32_t> x_column_;
  std::vector<int32_t> z_column_;  // -1: no epigraph column
  std::vector<double> cost_;
  double offset_ = 0;
  std::vector<std::vector<int64_t>> secants_;  // per bundle, the k in the model
  LpRowBatch pending_;
  std::unique_ptr<SparseDualSimplex> lp_;
};

LazyEpigraphLp::LazyEpigraphLp(const BundleObjectives& objectives,
                               std::span<const IntegerWindow> windows)
    : objectives_(objectives),
      windows_(windows),
      x_column_(objectives.num_bundles()),
      z_column_(objectives.num_bundles(), -1),
      secants_(objectives.num_bundles()) {
  int num_columns = objectives.num_bundles();
  for (const IntegerWindow& window : windows) num_columns += NeedsEpigraph(window) ? 1 : 0;
  lp_ = std::make_unique<SparseDualSimplex>(num_columns);
  cost_.assign(num_columns, 0.0);
  int next = 0;
  for (BundleId b = 0; b < objectives.num_bundles(); ++b) x_column_[b] = next++;
  for (BundleId b = 0; b < objectives.num_bundles(); ++b) {
    if (NeedsEpigraph(windows[b])) z_column_[b] = next++;
    AddBundleColumns(b);
  }
}

void LazyEpigraphLp::AddBundleColumns(BundleId b) {
  const IntegerWindow window = windows_[b];
  const int x = x_column_[b];
  lp_->SetColumnBounds(x, static_cast<double>(window.lo), static_cast<double>(window.hi));
  if (window.lo == window.hi) {
    offset_ += objectives_.Value(b, window.lo);
  } else if (!NeedsEpigraph(window)) {
    const Secant s = objectives_.SecantAt(b, window.lo);
    cost_[x] = s.slope;
    offset_ += s.value - s.slope * static_cast<double>(s.k);
  } else {
    // z_b is never below f_b's minimum over the integers: bounded, as the slack basis needs.
    const int z = z_column_[b];
    lp_->SetColumnBounds(z, objectives_.Value(b, objectives_.BestInteger(b)), kLpInfinity);
    cost_[z] = 1;
  }
  lp_->SetObjectiveCoefficient(x, cost_[x]);
  if (z_column_[b] >= 0) lp_->SetObjectiveCoefficient(z_column_[b], 1.0);
}

void LazyEpigraphLp::AddRows(const QuantizationConstraints& constraints) {
  AppendConstraintRows(constraints, x_column_, pending_);
}

void LazyEpigraphLp::AddSecant(BundleId b, int64_t k) {
  const IntegerWindow window = windows_[b];
  if (z_column_[b] < 0 || k < window.lo || k >= window.hi) return;
  std::vector<int64_t>& present = secants_[b];
  if (std::find(present.begin(), present.end(), k) != present.end()) return;
  present.push_back(k);
  // z - slope * x >= f(k) - slope * k
  const Secant s = objectives_.SecantAt(b, k);
  const int32_t columns[2] = {z_column_[b], x_column_[b]};
  const double coefs[2] = {1.0, -s.slope};
  pending_.Add(columns, coefs, s.value - s.slope * static_cast<double>(k), kLpInfinity);
}

void LazyEpigraphLp::AddSecantsAround(std::span<const int64_t> x) {
  for (BundleId b = 0; b < objectives_.num_bundles(); ++b) {
    AddSecant(b, x[b] - 1);
    AddSecant(b, x[b]);
  }
}

bool LazyEpigraphLp::AddViolatedSecants() {
  const int before = pending_.size();
  const std::span<const double> values = lp_->column_values();
  for (BundleId b = 0; b < objectives_.num_bundles(); ++b) {
    if (z_column_[b] < 0) continue;
    const IntegerWindow window = windows_[b];
    const double v = values[x_column_[b]];
    const double k = std::clamp(std::floor(v), static_cast<double>(window.lo),
                                static_cast<double>(window.hi - 1));
    const Secant s = objectives_.SecantAt(b, static_cast<int64_t>(k));
    const double needed = s.value + s.slope * (v - k);
    if (values[z_column_[b]] >= needed - 1e-9 * (1 + std::abs(needed))) continue;
    AddSecant(b, static_cast<int64_t>(k));
    // At a breakpoint the solution may leave toward either side.
    if (v - k < 1e-9) AddSecant(b, static_cast<int64_t>(k) - 1);
  }
  return pending_.size() > before;
}

SparseDualSimplex::Status LazyEpigraphLp::Solve() {
  if (pending_.size() > 0) {
    lp_->AddRows(pending_);
    pending_.Clear();
  }
  return lp_->Solve();
}

double LazyEpigraphLp::Objective() const {
  const std::span<const double> values = lp_->column_values();
  double sum = offset_;
  for (size_t j = 0; j < cost_.size(); ++j) sum += cost_[j] * values[j];
  return sum;
}

}  // namespace

std::optional<double> SolveLazyEpigraphRelaxation(const BundleObjectives& objectives,
                                                  const QuantizationConstraints& constraints,
                                                  std::span<const IntegerWindow> windows,
                                                  std::span<const int64_t> x) {
  LazyEpigraphLp lp(objectives, windows);
  lp.AddRows(constraints);
  lp.AddSecantsAround(x);
  for (int round = 0; round < kMaxRounds; ++round) {
    if (lp.Solve() != SparseDualSimplex::Status::kOptimal) return std::nullopt;
    if (!lp.AddViolatedSecants()) return lp.Objective();
  }
  return std::nullopt;
}

}  // namespace ispq
