// SPDX-License-Identifier: Apache-2.0
#include "core/isp/sheet_step.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/isp/integer_step.h"
#include "core/isp/lcd_scaling.h"
#include "core/status_macros.h"

namespace ispq {
namespace {

// Effectively unbounded multiplicity; the objective's vertex bounds real steps long before.
constexpr int64_t kUnboundedStep = int64_t{1} << 40;

// The fractional value closest to its next integer away from zero, or kNoId if none.
std::pair<BundleId, double> NearestToIntegerAwayFromZero(const RationalSheet& sheet) {
  BundleId best = kNoId;
  double best_gap = 2, best_value = 0;
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    const double v = sheet.values[i];
    const double gap = std::ceil(std::abs(v)) - std::abs(v);
    if (gap > 1e-6 && gap < best_gap) {
      best_gap = gap;
      best = sheet.bundles[i];
      best_value = v;
    }
  }
  return {best, best_value};
}

}  // namespace

SheetStepFinder::SheetStepFinder(const BundleQuantization& quantization, const InequalityRows& rows,
                                 const IspTuning& tuning, RunClock& clock, QuantizeStats& stats)
    : quantization_(quantization), rows_(rows), tuning_(tuning), clock_(clock), stats_(stats) {}

absl::StatusOr<bool> SheetStepFinder::Find(SheetSubproblem& subproblem, const SheetRequest& request,
                                           SheetStep* step) {
  if (clock_.ShouldStop()) return false;
  ISPQ_ASSIGN_OR_RETURN(const bool feasible, SolveRational(subproblem, request));
  if (!feasible) return false;
  if (tuning_.integer_dive && lcd_.has_value() && *lcd_ > 1) {
    ISPQ_RETURN_IF_ERROR(DiveToInteger(subproblem, request));
  }
  if (!ScaleToInteger(&step->sheet) || !subproblem.IsConsistent(step->sheet)) return false;
  int64_t t_max = kUnboundedStep;
  if (!RowsAllowStep(step->sheet, &t_max)) return false;
  PickMultiplicity(t_max, step);
  return true;
}

absl::StatusOr<bool> SheetStepFinder::SolveRational(SheetSubproblem& subproblem,
                                                    const SheetRequest& request) {
  const int64_t calls = subproblem.solver_calls();
  const int64_t flow_solves = subproblem.flow_solves();
  const SheetLpCounters before = subproblem.lp_counters();
  absl::StatusOr<bool> feasible = subproblem.Solve(request, &rational_);
  stats_.lp_solves += subproblem.solver_calls() - calls;
  stats_.flow_solves += subproblem.flow_solves() - flow_solves;
  const SheetLpCounters used = subproblem.lp_counters() - before;
  stats_.lp_pivots += used.pivots;
  stats_.lp_degenerate_pivots += used.degenerate_pivots;
  stats_.lp_refactorizations += used.refactorizations;
  stats_.lp_fallback_solves += used.fallback_solves;
  stats_.lp_stalled_solves += used.stalled_solves;
  if (!feasible.ok()) return feasible.status();
  if (!*feasible || rational_.bundles.empty()) return false;
  // Paper Fig. 8 counts the denominators of every rational solution computed.
  lcd_ = LeastCommonDenominator(rational_.values);
  if (!lcd_.has_value() || *lcd_ > 2) {
    ++stats_.lcd_more;
  } else if (*lcd_ == 2) {
    ++stats_.lcd_two;
  } else {
    ++stats_.lcd_one;
  }
  return true;
}

absl::Status SheetStepFinder::DiveToInteger(SheetSubproblem& subproblem,
                                            const SheetRequest& request) {
  SheetRequest dive = request;
  std::vector<std::pair<BundleId, int64_t>> fixed(request.fixed.begin(), request.fixed.end());
  RationalSheet last = rational_;
  std::optional<int64_t> last_lcd = lcd_;
  // Every iteration pins one more bundle, so the dive ends after at most one solve per bundle.
  const size_t max_pins = std::min(subproblem.bundles().size(), static_cast<size_t>(kMaxDivePins));
  for (size_t pinned = 0;
       pinned < max_pins && lcd_.has_value() && *lcd_ > 1 && !clock_.ShouldStop(); ++pinned) {
    const auto [best, best_value] = NearestToIntegerAwayFromZero(rational_);
    if (best == kNoId) break;
    const int64_t magnitude = static_cast<int64_t>(std::ceil(std::abs(best_value)));
    fixed.push_back({best, best_value > 0 ? magnitude : -magnitude});
    dive.fixed = fixed;
    ISPQ_ASSIGN_OR_RETURN(const bool feasible, SolveRational(subproblem, dive));
    if (!feasible) {
      // The pinned vertex does not exist: scale the last rational solution instead.
      rational_ = std::move(last);
      lcd_ = last_lcd;
      return absl::OkStatus();
    }
    last = rational_;
    last_lcd = lcd_;
  }
  return absl::OkStatus();
}

bool SheetStepFinder::ScaleToInteger(IntegerSheet* sheet) const {
  sheet->Clear();
  if (!lcd_.has_value()) return false;
  sheet->lcd = *lcd_;
  for (size_t i = 0; i < rational_.bundles.size(); ++i) {
    const int64_t d = std::llround(rational_.values[i] * static_cast<double>(*lcd_));
    if (d == 0) continue;
    sheet->bundles.push_back(rational_.bundles[i]);
    sheet->deltas.push_back(d);
  }
  return !sheet->empty();
}

bool SheetStepFinder::RowsAllowStep(const IntegerSheet& sheet, int64_t* t_max) {
  if (row_delta_.size() < static_cast<size_t>(rows_.size())) {
    row_delta_.resize(rows_.size(), 0);
    row_touched_.resize(rows_.size(), 0);
  }
  touched_rows_.clear();
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    for (const InequalityRows::Incidence& inc : rows_.rows_of_bundle(sheet.bundles[i])) {
      if (!row_touched_[inc.row]) {
        row_touched_[inc.row] = 1;
        touched_rows_.push_back(inc.row);
      }
      row_delta_[inc.row] += inc.coef * sheet.deltas[i];
    }
  }
  bool ok = true;
  for (int32_t r : touched_rows_) {
    const int64_t d = row_delta_[r];
    row_delta_[r] = 0;
    row_touched_[r] = 0;
    if (!ok || d == 0 || !rows_.active(r)) continue;
    const int64_t slack = rows_.slack(r);
    if (slack + d < 0) {
      ok = false;
    } else if (d < 0) {
      *t_max = std::min(*t_max, slack / -d);
    }
  }
  return ok;
}

void SheetStepFinder::PickMultiplicity(int64_t t_max, SheetStep* step) const {
  // OPTIMALINTEGERSTEP: the vertex of the convex objective along the sheet, clamped to [1, t_max].
  const StepQuadratic f = quantization_.Quadratic(step->sheet);
  step->t = OptimalIntegerStep(f.a, f.b, 1, t_max);
  step->gain = f.At(step->t);
}

}  // namespace ispq
