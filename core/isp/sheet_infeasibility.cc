// SPDX-License-Identifier: Apache-2.0
#include "core/isp/sheet_infeasibility.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ispq {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A row is refuted only if it must miss its bound by more than this: far beyond the LP solvers'
// feasibility tolerances (1e-8 and 1e-7), so a refuted request is infeasible for them too.
constexpr double kRefuteMargin = 1e-6;
// Bounds tighter by less than this are not propagated further (no endless creeping).
constexpr double kMinTightening = 1e-6;

}  // namespace

SheetInfeasibility::SheetInfeasibility(const SheetLpContext* context,
                                       std::span<const BundleId> bundles,
                                       std::span<const int32_t> equalities,
                                       const FlatLists<int32_t>* equalities_of_bundle)
    : context_(context),
      bundles_(bundles),
      equalities_(equalities),
      equalities_of_bundle_(equalities_of_bundle),
      bounds_stamp_(bundles.size(), 0),
      bounds_(bundles.size()) {}

SheetInfeasibility::Interval& SheetInfeasibility::Bounds(int32_t i) {
  Interval& bounds = bounds_[i];
  if (bounds_stamp_[i] == stamp_) return bounds;
  bounds_stamp_[i] = stamp_;
  // The mode's sign restrictions (SheetRequest::allow_*), and the bundle's floor row.
  bounds.lower = std::max(request_->allow_deflation ? -kInf : 0, Floor(bundles_[i]));
  bounds.upper = request_->allow_inflation ? kInf : 0;
  return bounds;
}

double SheetInfeasibility::Floor(BundleId b) const {
  return context_->has_floor[b] ? -static_cast<double>(context_->quantization->value(b)) : -kInf;
}

bool SheetInfeasibility::Tighten(int32_t i, double lower, double upper) {
  Interval& bounds = Bounds(i);
  bool tighter = false;
  if (lower > bounds.lower + kMinTightening) {
    bounds.lower = lower;
    tighter = true;
  }
  if (upper < bounds.upper - kMinTightening) {
    bounds.upper = upper;
    tighter = true;
  }
  if (bounds.lower > bounds.upper + kRefuteMargin) return false;
  if (tighter) QueueRowsOf(i);
  return true;
}

int32_t SheetInfeasibility::LpRowOf(int32_t code) const {
  // The equalities are the LP's first rows, in order (core/isp/sheet_subproblem.h).
  return code % 2 == 0 ? code / 2 : context_->lp_row_of_row[code / 2];
}

void SheetInfeasibility::QueueRowsOf(int32_t i) {
  auto queue = [&](int32_t code) {
    const int32_t lp_row = LpRowOf(code);
    if (static_cast<size_t>(lp_row) >= queued_stamp_.size()) {
      queued_stamp_.resize(2 * lp_row + 2, 0);
    }
    if (queued_stamp_[lp_row] == stamp_) return;
    queued_stamp_[lp_row] = stamp_;
    queue_.push_back(code);
  };
  for (int32_t k : (*equalities_of_bundle_)[i]) queue(2 * k);
  const InequalityRows& rows = *context_->rows;
  for (const InequalityRows::Incidence& inc : rows.rows_of_bundle(bundles_[i])) {
    const int32_t r = inc.row;
    if (!rows.active(r) || static_cast<size_t>(r) >= context_->lp_row_of_row.size() ||
        context_->lp_row_of_row[r] == kNoId) {
      continue;
    }
    queue(2 * r + 1);
  }
}

bool SheetInfeasibility::PropagateRow(std::span<const LinearTerm> terms, double lower,
                                      double upper) {
  // Activity bounds of the row, with the infinite contributions counted apart.
  double min_finite = 0, max_finite = 0;
  int min_infinite = 0, max_infinite = 0;
  auto contribution = [&](const LinearTerm& t, double* low, double* high) {
    const Interval& x = Bounds(context_->local_index_of_bundle[t.var]);
    const double a = t.coef;
    *low = a > 0 ? a * x.lower : a * x.upper;
    *high = a > 0 ? a * x.upper : a * x.lower;
  };
  for (const LinearTerm& t : terms) {
    double low, high;
    contribution(t, &low, &high);
    std::isinf(low) ? ++min_infinite : (min_finite += low, 0);
    std::isinf(high) ? ++max_infinite : (max_finite += high, 0);
  }
  if (max_infinite == 0 && max_finite < lower - kRefuteMargin) return false;
  if (min_infinite == 0 && min_finite > upper + kRefuteMargin) return false;
  for (const LinearTerm& t : terms) {
    double low, high;
    contribution(t, &low, &high);
    // The rest of the row without this term: a x >= lower - max(rest), a x <= upper - min(rest).
    const double max_rest = max_infinite == 0                       ? max_finite - high
                            : max_infinite == 1 && std::isinf(high) ? max_finite
                                                                    : kInf;
    const double min_rest = min_infinite == 0                      ? min_finite - low
                            : min_infinite == 1 && std::isinf(low) ? min_finite
                                                                   : -kInf;
    const double at_least = std::isinf(max_rest) || std::isinf(lower) ? -kInf : lower - max_rest;
    const double at_most = std::isinf(min_rest) || std::isinf(upper) ? kInf : upper - min_rest;
    const double a = t.coef;
    const double new_lower = a > 0 ? at_least / a : at_most / a;
    const double new_upper = a > 0 ? at_most / a : at_least / a;
    if (!Tighten(context_->local_index_of_bundle[t.var], new_lower, new_upper)) return false;
  }
  return true;
}

bool SheetInfeasibility::Refutes(const SheetRequest& request) {
  if (request.root == kNoId) return false;  // separating solves: the rows decide
  request_ = &request;
  if (++stamp_ == 0) {  // wrapped: forget every old stamp
    std::fill(bounds_stamp_.begin(), bounds_stamp_.end(), 0);
    std::fill(queued_stamp_.begin(), queued_stamp_.end(), 0);
    stamp_ = 1;
  }
  queue_.clear();
  const std::vector<int32_t>& local = context_->local_index_of_bundle;
  // The request's own bounds, in the order SheetSubproblem sets them: blocked directions, then
  // the root and the pinned bundles, which override them; the floors hold throughout.
  for (const auto& [b, inflation] : request.blocked) {
    if (!Tighten(local[b], inflation ? -kInf : 0, inflation ? 0 : kInf)) return true;
  }
  auto set = [&](BundleId b, double lower, double upper) {
    const int32_t i = local[b];
    Interval& bounds = Bounds(i);
    bounds.lower = std::max(lower, Floor(b));
    bounds.upper = upper;
    QueueRowsOf(i);
    return bounds.lower <= bounds.upper + kRefuteMargin;
  };
  if (!(request.inflate_root ? set(request.root, 1, kInf) : set(request.root, -kInf, -1))) {
    return true;
  }
  for (const auto& [b, value] : request.fixed) {
    if (!set(b, static_cast<double>(value), static_cast<double>(value))) return true;
  }
  const InequalityRows& rows = *context_->rows;
  for (size_t k = 0; k < queue_.size() && k < static_cast<size_t>(kMaxRowVisits); ++k) {
    const int32_t code = queue_[k];
    queued_stamp_[LpRowOf(code)] = 0;  // it may be queued again
    const bool holds =
        code % 2 == 0
            ? PropagateRow((*context_->equalities)[equalities_[code / 2]], 0, 0)
            : PropagateRow(rows.terms(code / 2), -static_cast<double>(rows.slack(code / 2)), kInf);
    if (!holds) return true;
  }
  return false;
}

}  // namespace ispq
