// SPDX-License-Identifier: Apache-2.0
#include "core/isp/sheet_subproblem.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/isp/sheet_weights.h"

namespace ispq {
namespace {

// LP values below this are simplex noise, not part of the sheet.
constexpr double kZeroTolerance = 1e-7;

// Per bundle of `bundles` (ascending), the consistency rows through it, by their positions in
// `equalities`.
FlatLists<int32_t> EqualitiesOfBundles(const SheetLpContext& context,
                                       std::span<const BundleId> bundles,
                                       std::span<const int32_t> equalities) {
  std::vector<std::vector<int32_t>> lists(bundles.size());
  for (int32_t k = 0; k < static_cast<int32_t>(equalities.size()); ++k) {
    for (const LinearTerm& t : (*context.equalities)[equalities[k]]) {
      lists[std::lower_bound(bundles.begin(), bundles.end(), t.var) - bundles.begin()].push_back(k);
    }
  }
  FlatLists<int32_t> flat;
  for (const std::vector<int32_t>& list : lists) flat.Append(list);
  return flat;
}

}  // namespace

SheetSubproblem::SheetSubproblem(SheetLpContext* context, std::vector<BundleId> bundles,
                                 std::vector<int32_t> equalities, std::vector<int32_t> rows)
    : context_(context),
      bundles_(std::move(bundles)),
      equalities_(std::move(equalities)),
      rows_(std::move(rows)),
      equalities_of_bundle_(EqualitiesOfBundles(*context, bundles_, equalities_)),
      infeasibility_(context, bundles_, equalities_, &equalities_of_bundle_),
      cap_(context->column_cap) {
  for (size_t i = 0; i < bundles_.size(); ++i) {
    context_->local_index_of_bundle[bundles_[i]] = static_cast<int32_t>(i);
  }
  bundle_dirty_.assign(bundles_.size(), 0);
  scratch_delta_.assign(bundles_.size(), 0);
  Build();
}

void SheetSubproblem::AppendRow(std::span<const LinearTerm> terms, double lower, double upper,
                                LpRowBatch* batch) {
  // A bundle term c * x_b becomes c * Delta+ - c * Delta- on the bundle's column pair.
  columns_.clear();
  coefs_.clear();
  for (const LinearTerm& t : terms) {
    const int32_t i = context_->local_index_of_bundle[t.var];
    columns_.push_back(2 * i);
    coefs_.push_back(t.coef);
    columns_.push_back(2 * i + 1);
    coefs_.push_back(-t.coef);
  }
  batch->Add(columns_, coefs_, lower, upper);
}

double SheetSubproblem::RowLowerBound(int32_t r) const {
  // Eqs. 6a/6b: B (q_pre + Delta) >= rhs, i.e. B Delta >= rhs - B q_pre = -slack.
  const InequalityRows& rows = *context_->rows;
  return rows.active(r) ? static_cast<double>(-rows.slack(r)) : -kLpInfinity;
}

void SheetSubproblem::Build() {
  lp_ = context_->new_lp(2 * static_cast<int>(bundles_.size()));
  cap_ = UsualCap();
  LpRowBatch batch;
  for (int32_t e : equalities_) AppendRow((*context_->equalities)[e], 0.0, 0.0, &batch);
  lp_->AddRows(batch);
  std::vector<int32_t> rows;
  rows.swap(rows_);
  AddRows(rows);
  for (BundleId b : bundles_) PushWeights(b);
  ResetAllColumnPairs();
}

void SheetSubproblem::AddRows(std::span<const int32_t> new_rows) {
  if (new_rows.empty()) return;
  LpRowBatch batch;
  for (int32_t r : new_rows) {
    context_->lp_row_of_row[r] = lp_->num_rows() + batch.size();
    rows_.push_back(r);
    AppendRow(context_->rows->terms(r), RowLowerBound(r), kLpInfinity, &batch);
  }
  lp_->AddRows(batch);
}

void SheetSubproblem::MarkBundleMoved(BundleId b) {
  const int32_t i = context_->local_index_of_bundle[b];
  if (!bundle_dirty_[i]) {
    bundle_dirty_[i] = 1;
    dirty_bundles_.push_back(b);
  }
  for (const InequalityRows::Incidence& inc : context_->rows->rows_of_bundle(b)) {
    dirty_rows_.push_back(inc.row);
  }
}

void SheetSubproblem::MarkRowChanged(int32_t r) { dirty_rows_.push_back(r); }

void SheetSubproblem::PushRowBounds(int32_t r) {
  const int32_t lp_row = context_->lp_row_of_row[r];
  if (lp_row == kNoId) return;  // a failsafe row not (yet) in any LP
  lp_->SetRowBounds(lp_row, RowLowerBound(r), kLpInfinity);
}

BundleWeights SheetSubproblem::WeightsOf(BundleId b) const {
  const BundleQuantization& x = *context_->quantization;
  const double value = static_cast<double>(x.value(b));
  switch (weights_) {
    case WeightScheme::kTiered:
      return BundleSheetWeights(x.targets(b), value, context_->num_arcs);
    case WeightScheme::kMarginalCost:
      return BundleMarginalWeights(x.targets(b), value, 1e-3);
    case WeightScheme::kUnitCost:
      return BundleUnitCosts(x.targets(b), value);
  }
  return {0, 0};
}

void SheetSubproblem::PushWeights(BundleId b) {
  const BundleWeights w = WeightsOf(b);
  const int32_t i = context_->local_index_of_bundle[b];
  lp_->SetObjectiveCoefficient(2 * i, w.inflate);
  lp_->SetObjectiveCoefficient(2 * i + 1, w.deflate);
}

double SheetSubproblem::DeflationCap(BundleId b) const {
  return context_->has_floor[b] ? static_cast<double>(context_->quantization->value(b))
                                : kLpInfinity;
}

void SheetSubproblem::ResetColumnPair(int32_t local) {
  lp_->SetColumnBounds(2 * local, 0, allow_inflation_ ? cap_ : 0);
  lp_->SetColumnBounds(2 * local + 1, 0, allow_deflation_ ? cap_ : 0);
}

void SheetSubproblem::ResetAllColumnPairs() {
  for (int32_t i = 0; i < static_cast<int32_t>(bundles_.size()); ++i) ResetColumnPair(i);
}

void SheetSubproblem::SetMode(bool allow_inflation, bool allow_deflation) {
  if (allow_inflation == allow_inflation_ && allow_deflation == allow_deflation_) return;
  allow_inflation_ = allow_inflation;
  allow_deflation_ = allow_deflation;
  ResetAllColumnPairs();
}

absl::StatusOr<bool> SheetSubproblem::Solve(const SheetRequest& request, RationalSheet* sheet) {
  PushPendingEdits(request.weights);
  if (request.unit_moves) return SolveUnitMoves(request, sheet);
  if (const std::optional<bool> answered = SolveAsFlow(request, kLpInfinity, sheet)) {
    return *answered;
  }
  if (!SetRequestBounds(request)) return false;
  if (context_->refute_by_propagation && infeasibility_.Refutes(request)) {
    ++refuted_requests_;
    return false;
  }
  absl::StatusOr<LpOutcome> outcome = RunSolver();
  if (!outcome.ok()) return outcome.status();
  if (*outcome == LpOutcome::kStopped) return false;
  const bool optimal = *outcome == LpOutcome::kOptimal;
  const bool reaches_cap = optimal && ReadSheet(sheet);
  if ((optimal && !reaches_cap) || std::isinf(cap_)) return optimal;
  // The cap may have cut off the optimum, or every solution: once more without it, then back.
  ++uncapped_solves_;
  cap_ = kLpInfinity;
  ResetAllColumnPairs();
  SetRequestBounds(request);
  outcome = RunSolver();
  const bool uncapped_optimal = outcome.ok() && *outcome == LpOutcome::kOptimal;
  if (uncapped_optimal) ReadSheet(sheet);
  cap_ = UsualCap();
  ResetAllColumnPairs();
  if (!outcome.ok()) return outcome.status();
  return uncapped_optimal;
}

std::optional<bool> SheetSubproblem::SolveAsFlow(const SheetRequest& request, double bound,
                                                 RationalSheet* sheet) {
  if (context_->potentials == nullptr || bundles_.size() < context_->flow_min_bundles ||
      request.root != kNoId || !request.blocked.empty() || !request.fixed.empty()) {
    return std::nullopt;
  }
  if (network_ == nullptr) {
    network_ = std::make_unique<SheetNetwork>(*context_->potentials, bundles_,
                                              context_->local_index_of_bundle);
  }
  network_weights_.resize(bundles_.size());
  for (size_t i = 0; i < bundles_.size(); ++i) network_weights_[i] = WeightsOf(bundles_[i]);
  const SheetNetwork::Outcome outcome = network_->Solve(
      network_weights_, request.allow_inflation ? bound : 0, request.allow_deflation ? bound : 0,
      *context_->rows, rows_, context_->should_stop, &moves_);
  if (outcome == SheetNetwork::Outcome::kUnanswered) return std::nullopt;
  // On a part with handles a descent the flow cannot continue may still go on in the LP, which
  // moves periods, if the request asks.
  if (request.unit_moves && request.confirm_stalled_flow &&
      outcome == SheetNetwork::Outcome::kOptimal && network_->holds_periods() &&
      network_->answer_cost() >= -context_->quantization->GainTolerance()) {
    return std::nullopt;
  }
  ++solver_calls_;
  ++flow_solves_;
  if (outcome != SheetNetwork::Outcome::kOptimal) return false;
  sheet->bundles.clear();
  sheet->values.clear();
  for (const auto& [b, move] : moves_) {
    sheet->bundles.push_back(b);
    sheet->values.push_back(static_cast<double>(move));
  }
  return true;
}

absl::StatusOr<bool> SheetSubproblem::SolveUnitMoves(const SheetRequest& request,
                                                     RationalSheet* sheet) {
  if (const std::optional<bool> answered = SolveAsFlow(request, 1, sheet)) return *answered;
  // The box of one unit is the request itself, not a cap that could cut off an answer: no repeat
  // without it. Every column pair is reset twice, O(bundles), which the descent's few solves
  // over the whole subproblem can afford.
  cap_ = 1;
  ResetAllColumnPairs();
  const bool feasible = SetRequestBounds(request);
  const absl::StatusOr<LpOutcome> outcome =
      feasible ? RunSolver() : absl::StatusOr<LpOutcome>(LpOutcome::kInfeasible);
  const bool optimal = outcome.ok() && *outcome == LpOutcome::kOptimal;
  if (optimal) ReadSheet(sheet);
  cap_ = UsualCap();
  ResetAllColumnPairs();
  if (!outcome.ok()) return outcome.status();
  return optimal;
}

void SheetSubproblem::PushPendingEdits(WeightScheme weights) {
  if (weights != weights_) {
    weights_ = weights;
    for (BundleId b : bundles_) MarkBundleMoved(b);
  }
  for (BundleId b : dirty_bundles_) {
    PushWeights(b);
    const int32_t i = context_->local_index_of_bundle[b];
    bundle_dirty_[i] = 0;
  }
  dirty_bundles_.clear();
  for (int32_t r : dirty_rows_) PushRowBounds(r);
  dirty_rows_.clear();
}

bool SheetSubproblem::SetRequestBounds(const SheetRequest& request) {
  if (root_local_ != kNoId) ResetColumnPair(root_local_);
  root_local_ = kNoId;
  for (int32_t i : blocked_locals_) ResetColumnPair(i);
  blocked_locals_.clear();
  SetMode(request.allow_inflation, request.allow_deflation);
  for (const auto& [b, inflation] : request.blocked) {
    const int32_t i = context_->local_index_of_bundle[b];
    lp_->SetColumnBounds(inflation ? 2 * i : 2 * i + 1, 0, 0);
    blocked_locals_.push_back(i);
  }
  if (request.root != kNoId) {
    root_local_ = context_->local_index_of_bundle[request.root];
    const int plus = 2 * root_local_, minus = plus + 1;
    if (request.inflate_root) {
      lp_->SetColumnBounds(plus, 1, cap_);
      lp_->SetColumnBounds(minus, 0, 0);
    } else {
      // A root at its floor cannot deflate: no need to ask the solver.
      if (DeflationCap(request.root) < 1) return false;
      lp_->SetColumnBounds(plus, 0, 0);
      lp_->SetColumnBounds(minus, 1, cap_);
    }
  }

  // Fixed values come last: they may pin the root to more than its pump bound.
  for (const auto& [b, value] : request.fixed) {
    const int32_t i = context_->local_index_of_bundle[b];
    const double v = static_cast<double>(value);
    if (-v > DeflationCap(b)) return false;  // below the bundle's floor
    lp_->SetColumnBounds(2 * i, std::max(v, 0.0), std::max(v, 0.0));
    lp_->SetColumnBounds(2 * i + 1, std::max(-v, 0.0), std::max(-v, 0.0));
    blocked_locals_.push_back(i);
  }
  return true;
}

absl::StatusOr<LpOutcome> SheetSubproblem::RunSolver() {
  ++solver_calls_;
  const SheetLpCounters before = lp_->counters();
  const absl::StatusOr<LpOutcome> outcome = lp_->Solve();
  lp_counters_ += lp_->counters() - before;
  return outcome;
}

double SheetSubproblem::UsualCap() const {
  return lp_->wants_column_cap() ? context_->column_cap : kLpInfinity;
}

bool SheetSubproblem::ReadSheet(RationalSheet* sheet) {
  sheet->bundles.clear();
  sheet->values.clear();
  const std::span<const double> x = lp_->column_values();
  const double cap_reached = cap_ - kZeroTolerance;  // +inf without a cap
  // The column pairs with a non-zero column, ascending (so are their bundles).
  nonzero_columns_.clear();
  lp_->AppendNonzeroColumns(&nonzero_columns_);
  for (int32_t& j : nonzero_columns_) j /= 2;
  std::sort(nonzero_columns_.begin(), nonzero_columns_.end());
  nonzero_columns_.erase(std::unique(nonzero_columns_.begin(), nonzero_columns_.end()),
                         nonzero_columns_.end());
  bool at_cap = false;
  for (const int32_t i : nonzero_columns_) {
    at_cap |= x[2 * i] >= cap_reached || x[2 * i + 1] >= cap_reached;
    const double v = x[2 * i] - x[2 * i + 1];
    if (std::abs(v) > kZeroTolerance) {
      sheet->bundles.push_back(bundles_[i]);
      sheet->values.push_back(v);
    }
  }
  return at_cap;
}

bool SheetSubproblem::IsConsistent(const IntegerSheet& sheet) {
  // Only the consistency rows through the sheet's bundles can be violated by it.
  const std::vector<int32_t>& local = context_->local_index_of_bundle;
  for (size_t k = 0; k < sheet.bundles.size(); ++k) {
    scratch_delta_[local[sheet.bundles[k]]] = sheet.deltas[k];
  }
  bool consistent = true;
  for (size_t k = 0; k < sheet.bundles.size() && consistent; ++k) {
    for (int32_t position : equalities_of_bundle_[local[sheet.bundles[k]]]) {
      int64_t sum = 0;
      for (const LinearTerm& t : (*context_->equalities)[equalities_[position]]) {
        sum += t.coef * scratch_delta_[local[t.var]];
      }
      if (sum != 0) {
        consistent = false;
        break;
      }
    }
  }
  for (BundleId b : sheet.bundles) scratch_delta_[local[b]] = 0;
  return consistent;
}

}  // namespace ispq
