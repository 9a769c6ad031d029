// SPDX-License-Identifier: Apache-2.0
#include "core/exact/quantization_milp.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/exact/window_slacks.h"
#include "core/quantization_limits.h"

namespace ispq {
namespace {

// One bundle's objective: a constant, a linear term or an epigraph column with its secants.
void AddBundleObjective(const BundleObjectives& objectives, BundleId b, IntegerWindow window,
                        QuantizationMilp& milp) {
  MilpModel& model = milp.model;
  const int x = milp.x_column[b];
  if (window.lo == window.hi) {
    model.objective_offset += objectives.Value(b, window.lo);
    return;
  }
  if (window.hi == window.lo + 1) {
    const Secant s = objectives.SecantAt(b, window.lo);
    model.objective[x] += s.slope;
    model.objective_offset += s.value - s.slope * static_cast<double>(s.k);
    return;
  }
  // z_b is never below f_b's minimum over the integers, which tightens the relaxation a little.
  const int z =
      model.AddColumn(objectives.Value(b, objectives.BestInteger(b)), kLpInfinity, 1.0, false);
  milp.z_column[b] = z;
  for (int64_t k = window.lo; k < window.hi; ++k) {
    // z - slope * x >= f(k) - slope * k
    const Secant s = objectives.SecantAt(b, k);
    const int32_t columns[2] = {z, x};
    const double coefs[2] = {1.0, -s.slope};
    model.rows.Add(columns, coefs, s.value - s.slope * static_cast<double>(k), kLpInfinity);
  }
}

// Bundle b's window holds the integers within slacks[b] of its best value.
std::vector<IntegerWindow> WindowsOf(const BundleObjectives& objectives,
                                     std::span<const double> slacks) {
  std::vector<IntegerWindow> windows(objectives.num_bundles());
  for (BundleId b = 0; b < objectives.num_bundles(); ++b) {
    windows[b] = objectives.Window(b, slacks[b]);
  }
  return windows;
}

absl::StatusOr<QuantizationMilp> BuildWithWindows(const BundleObjectives& objectives,
                                                  const QuantizationConstraints& constraints,
                                                  std::span<const IntegerWindow> windows) {
  const int n = objectives.num_bundles();
  int64_t secants = 0;
  for (const IntegerWindow& window : windows) secants += window.hi - window.lo;
  if (secants > kMaxSecantRows) {
    return absl::ResourceExhaustedError(
        absl::StrCat("the objective bound is too far above the minimum for an exact model (",
                     secants, " secants)"));
  }
  QuantizationMilp milp;
  milp.x_column.resize(n);
  milp.z_column.assign(n, -1);
  for (BundleId b = 0; b < n; ++b) {
    milp.x_column[b] = milp.model.AddColumn(static_cast<double>(windows[b].lo),
                                            static_cast<double>(windows[b].hi), 0.0, true);
  }
  for (BundleId b = 0; b < n; ++b) AddBundleObjective(objectives, b, windows[b], milp);
  AppendConstraintRows(constraints, milp.x_column, milp.model.rows);
  return milp;
}

absl::StatusOr<QuantizationMilp> BuildWithSlacks(const BundleObjectives& objectives,
                                                 const QuantizationConstraints& constraints,
                                                 std::span<const double> slacks) {
  for (double slack : slacks) {
    if (!std::isfinite(slack)) {
      return absl::ResourceExhaustedError("an exact model needs a finite objective bound");
    }
  }
  return BuildWithWindows(objectives, constraints, WindowsOf(objectives, slacks));
}

// A little slack so that the known q itself is never cut off by rounding.
double WithMargin(double slack, double scale) { return slack + 1e-9 * (1 + std::abs(scale)); }

// The window slacks for a known q (per-bundle values x), with margins.
std::vector<double> SlacksFor(const BundleObjectives& objectives,
                              const QuantizationConstraints& constraints,
                              std::span<const int64_t> x) {
  std::vector<double> slacks = WindowSlacks(objectives, constraints, x);
  const double scale = objectives.Objective(x);
  for (double& slack : slacks) slack = WithMargin(slack, scale);
  return slacks;
}

}  // namespace

void AppendConstraintRows(const QuantizationConstraints& constraints, std::span<const int> x_column,
                          LpRowBatch& rows) {
  std::vector<int32_t> columns;
  std::vector<double> coefs;
  const auto add = [&](std::span<const LinearTerm> terms, double lower, double upper) {
    columns.clear();
    coefs.clear();
    for (const LinearTerm& t : terms) {
      columns.push_back(x_column[t.var]);
      coefs.push_back(static_cast<double>(t.coef));
    }
    rows.Add(columns, coefs, lower, upper);
  };
  for (int i = 0; i < constraints.num_equalities(); ++i) add(constraints.equality(i), 0, 0);
  for (int i = 0; i < constraints.num_inequalities(); ++i) {
    add(constraints.inequality(i), static_cast<double>(constraints.rhs(i)), kLpInfinity);
  }
}

std::vector<IntegerWindow> ModelWindows(const BundleObjectives& objectives,
                                        const QuantizationConstraints& constraints,
                                        std::span<const int64_t> x) {
  return WindowsOf(objectives, SlacksFor(objectives, constraints, x));
}

absl::StatusOr<QuantizationMilp> BuildQuantizationMilp(const BundleObjectives& objectives,
                                                       const QuantizationConstraints& constraints,
                                                       std::span<const int64_t> x) {
  return BuildWithSlacks(objectives, constraints, SlacksFor(objectives, constraints, x));
}

absl::StatusOr<QuantizationMilp> BuildQuantizationMilp(const BundleObjectives& objectives,
                                                       const QuantizationConstraints& constraints,
                                                       double upper_bound) {
  const std::vector<double> slacks(objectives.num_bundles(),
                                   WithMargin(upper_bound - objectives.MinimumSum(), upper_bound));
  return BuildWithSlacks(objectives, constraints, slacks);
}

MilpModel BuildFeasibilityModel(int num_bundles, const QuantizationConstraints& constraints) {
  MilpModel model;
  std::vector<int> x_column(num_bundles);
  const double limit = static_cast<double>(kMaxArcLength);
  for (BundleId b = 0; b < num_bundles; ++b) x_column[b] = model.AddColumn(-limit, limit, 0, true);
  AppendConstraintRows(constraints, x_column, model.rows);
  return model;
}

std::optional<std::vector<double>> QuantizationMilp::ColumnsOf(const BundleObjectives& objectives,
                                                               std::span<const int64_t> x) const {
  std::vector<double> columns(model.num_columns(), 0.0);
  for (BundleId b = 0; b < static_cast<BundleId>(x_column.size()); ++b) {
    const double value = static_cast<double>(x[b]);
    const int c = x_column[b];
    if (value < model.column_lower[c] || value > model.column_upper[c]) return std::nullopt;
    columns[c] = value;
    if (z_column[b] >= 0) columns[z_column[b]] = objectives.Value(b, x[b]);
  }
  return columns;
}

std::vector<int64_t> QuantizationMilp::BundleValuesOf(std::span<const double> columns) const {
  std::vector<int64_t> x(x_column.size());
  for (size_t b = 0; b < x.size(); ++b) x[b] = std::llround(columns[x_column[b]]);
  return x;
}

}  // namespace ispq
