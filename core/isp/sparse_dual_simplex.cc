// SPDX-License-Identifier: Apache-2.0
#include "core/isp/sparse_dual_simplex.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "CoinFactorization.hpp"
#include "CoinIndexedVector.hpp"
#include "core/invariant.h"
#include "core/linear_terms.h"

namespace ispq {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Entries of FTRAN/BTRAN results below this are cancellation noise (CoinIndexedVector keeps
// cancelled entries as 1e-100).
constexpr double kNoise = 1e-12;
// Candidates found feasible by their refreshed value, since the last pivot, before all the kept
// values are recomputed at once (a recomputation costs about as much as a few pivot rows).
constexpr int kDropsBeforeRecompute = 8;
// The pivot element seen in the pivot row and in the FTRAN'd entering column must agree to this
// relative accuracy, else the factorization has drifted and is rebuilt.
constexpr double kPivotAgreement = 1e-7;

bool IsFinite(double x) { return std::abs(x) < kInf; }

}  // namespace

SparseDualSimplex::SparseDualSimplex(int num_columns, const SparseDualSimplexOptions& options)
    : options_(options),
      num_columns_(num_columns),
      column_start_(num_columns + 1, 0),
      lower_(num_columns, 0.0),
      upper_(num_columns, kInf),
      cost_(num_columns, 0.0),
      value_(num_columns, 0.0),
      reduced_cost_(num_columns, 0.0),
      status_(num_columns, VarStatus::kAtLower),
      position_(num_columns, -1),
      edge_weight_(num_columns, 1.0),
      factorization_(std::make_unique<CoinFactorization>()),
      work_(std::make_unique<CoinIndexedVector>()),
      column_(std::make_unique<CoinIndexedVector>()),
      row_(std::make_unique<CoinIndexedVector>()),
      pending_primal_(std::make_unique<CoinIndexedVector>()),
      pending_cost_(std::make_unique<CoinIndexedVector>()),
      is_nonzero_nonbasic_(num_columns, 0),
      alpha_(num_columns, 0.0) {
  // 1: a refactorization reuses the arrays of the one before unless it needs bigger ones. By
  // default CoinFactorization frees and allocates its areas anew every time (4-12 MB each on a
  // 300k-arc part); glibc then serves them from the heap, where they fragment it. At 300k arcs
  // this lowered peak RSS by 3-10% at levels 25 and 100 (0-3% higher at level 5), CPU within 3%; q
  // identical on the shared set.
  factorization_->setPersistenceFlag(1);
}

SparseDualSimplex::~SparseDualSimplex() = default;

// ---------------------------------------------------------------------------------------------
// Edits

void SparseDualSimplex::SetObjectiveCoefficient(int column, double value) {
  const double delta = value - cost_[column];
  if (delta == 0) return;
  cost_[column] = value;
  ++costs_changed_;
  if (!factorization_valid_) return;  // the next refactorization recomputes every reduced cost
  if (status_[column] == VarStatus::kBasic) {
    // y changes by B^-T (delta e_position): deferred to one BTRAN for all such edits.
    pending_cost_->quickAdd(position_[column], delta);
    has_pending_cost_ = true;
  } else {
    reduced_cost_[column] += delta;
    dual_check_.push_back(column);
  }
}

void SparseDualSimplex::SetColumnBounds(int column, double lower, double upper) {
  lower_[column] = lower;
  upper_[column] = upper;
  if (status_[column] == VarStatus::kBasic) {
    if (factorization_valid_) MarkPrimalCandidate(position_[column]);
  } else {
    PlaceNonbasic(column);
    dual_check_.push_back(column);
  }
}

void SparseDualSimplex::SetRowBounds(int row, double lower, double upper) {
  const int v = num_columns_ + row;
  lower_[v] = lower;
  upper_[v] = upper;
  if (status_[v] == VarStatus::kBasic) {
    if (factorization_valid_) MarkPrimalCandidate(position_[v]);
  } else {
    PlaceNonbasic(v);
    dual_check_.push_back(v);
  }
}

void SparseDualSimplex::AddRows(const LpRowBatch& batch) {
  if (batch.size() == 0) return;
  for (int k = 0; k < batch.size(); ++k) {
    // Repeated columns are merged (the factorization wants each entry once) and zeros dropped.
    new_row_.clear();
    for (int32_t t = batch.starts()[k]; t < batch.starts()[k + 1]; ++t) {
      new_row_.push_back({batch.columns()[t], batch.coefs()[t]});
    }
    MergeRepeatedTerms(new_row_);
    for (const ColumnTerm& term : new_row_) {
      row_column_.push_back(term.var);
      row_coef_.push_back(term.coef);
    }
    row_start_.push_back(static_cast<int32_t>(row_column_.size()));
    // The new row's logical joins the basis; its value is set by the refactorization.
    lower_.push_back(batch.lower()[k]);
    upper_.push_back(batch.upper()[k]);
    cost_.push_back(0);
    value_.push_back(0);
    reduced_cost_.push_back(0);
    status_.push_back(VarStatus::kBasic);
    position_.push_back(-1);
    alpha_.push_back(0);
    edge_weight_.push_back(1);
    is_nonzero_nonbasic_.push_back(0);
  }
  num_rows_ += batch.size();
  // The column copy, rebuilt from the row copy.
  std::fill(column_start_.begin(), column_start_.end(), 0);
  for (int32_t j : row_column_) ++column_start_[j + 1];
  for (int j = 0; j < num_columns_; ++j) column_start_[j + 1] += column_start_[j];
  column_row_.resize(row_column_.size());
  column_coef_.resize(row_column_.size());
  std::vector<int32_t> next(column_start_.begin(), column_start_.end() - 1);
  for (int i = 0; i < num_rows_; ++i) {
    for (int32_t t = row_start_[i]; t < row_start_[i + 1]; ++t) {
      const int32_t k = next[row_column_[t]]++;
      column_row_[k] = i;
      column_coef_[k] = row_coef_[t];
    }
  }
  factorization_valid_ = false;
}

void SparseDualSimplex::PlaceNonbasic(int v) {
  const double l = lower_[v], u = upper_[v];
  double target;
  if (l == u) {
    status_[v] = VarStatus::kAtLower;
    target = l;
  } else if (IsFinite(l) && (reduced_cost_[v] >= 0 || !IsFinite(u))) {
    status_[v] = VarStatus::kAtLower;
    target = l;
  } else if (IsFinite(u)) {
    status_[v] = VarStatus::kAtUpper;
    target = u;
  } else {
    status_[v] = VarStatus::kFree;
    target = 0;
  }
  MoveNonbasicTo(v, target);
}

void SparseDualSimplex::MoveNonbasicTo(int v, double value) {
  const double delta = value - value_[v];
  if (delta == 0) return;
  value_[v] = value;
  NoteNonbasicValue(v);
  if (!factorization_valid_) return;  // the refactorization recomputes the basic values
  // x_B = -B^-1 N x_N: deferred to one FTRAN for all moved nonbasic variables.
  AddColumnTo(v, delta, pending_primal_.get());
  has_pending_primal_ = true;
}

void SparseDualSimplex::AddColumnTo(int v, double scale, CoinIndexedVector* vector) const {
  if (IsLogical(v)) {
    vector->quickAdd(v - num_columns_, -scale);
    return;
  }
  for (int32_t t = column_start_[v]; t < column_start_[v + 1]; ++t) {
    vector->quickAdd(column_row_[t], scale * column_coef_[t]);
  }
}

void SparseDualSimplex::ApplyPendingPrimalChange() {
  if (!has_pending_primal_) return;
  has_pending_primal_ = false;
  factorization_->updateColumn(work_.get(), pending_primal_.get());
  const double* w = pending_primal_->denseVector();
  const int* index = pending_primal_->getIndices();
  for (int k = 0; k < pending_primal_->getNumElements(); ++k) {
    const int position = index[k];
    if (w[position] == 0) continue;
    value_[basic_variable_[position]] -= w[position];
    NoteBasicValue(position);
    MarkPrimalCandidate(position);
  }
  pending_primal_->clear();
}

template <typename Share>
void SparseDualSimplex::ForEachNonbasicShare(const CoinIndexedVector& y, Share&& share) const {
  const double* dense = y.denseVector();
  const int* index = y.getIndices();
  for (int k = 0; k < y.getNumElements(); ++k) {
    const int row = index[k];
    const double y_row = dense[row];
    if (std::abs(y_row) < kNoise) continue;
    const int logical = num_columns_ + row;
    if (status_[logical] != VarStatus::kBasic) share(logical, -y_row);  // its column is -e_row
    for (int32_t t = row_start_[row]; t < row_start_[row + 1]; ++t) {
      const int32_t j = row_column_[t];
      if (status_[j] != VarStatus::kBasic) share(j, y_row * row_coef_[t]);
    }
  }
}

void SparseDualSimplex::ApplyPendingCostChange() {
  if (!has_pending_cost_) return;
  has_pending_cost_ = false;
  // delta y = B^-T delta c_B; every nonbasic reduced cost d_v = c_v - col_v^T y moves with it.
  factorization_->updateColumnTranspose(work_.get(), pending_cost_.get());
  ForEachNonbasicShare(*pending_cost_, [this](int v, double share) {
    reduced_cost_[v] -= share;
    dual_check_.push_back(v);
  });
  pending_cost_->clear();
}

double SparseDualSimplex::DualTolerance(int v) const {
  // Absolute, plus the rounding error a reduced cost of this magnitude carries.
  return options_.dual_tolerance + 1e-14 * std::abs(cost_[v]);
}

bool SparseDualSimplex::DualInfeasible(int v) const {
  if (lower_[v] == upper_[v]) return false;
  const double d = reduced_cost_[v], tol = DualTolerance(v);
  switch (status_[v]) {
    case VarStatus::kAtLower:
      return d < -tol;
    case VarStatus::kAtUpper:
      return d > tol;
    case VarStatus::kFree:
      return std::abs(d) > tol;
    case VarStatus::kBasic:
      return false;
  }
  return false;
}

bool SparseDualSimplex::RepairDualFeasibility() {
  bool repaired = true;
  for (int32_t v : dual_check_) {
    if (status_[v] == VarStatus::kBasic || !DualInfeasible(v)) continue;
    const double d = reduced_cost_[v];
    if (d < 0) {
      // Without a finite upper bound the column goes to an artificial one, which the solve must
      // leave behind (see Solve()).
      status_[v] = VarStatus::kAtUpper;
      if (IsFinite(upper_[v])) {
        MoveNonbasicTo(v, upper_[v]);
      } else {
        MoveNonbasicTo(v, options_.artificial_bound);
        at_artificial_bound_.push_back(v);
      }
    } else if (d > 0 && IsFinite(lower_[v])) {
      status_[v] = VarStatus::kAtLower;
      MoveNonbasicTo(v, lower_[v]);
    } else {
      repaired = false;
      break;
    }
  }
  dual_check_.clear();
  return repaired;
}

bool SparseDualSimplex::LeftArtificialBounds() {
  // A column still at its artificial bound at the end would move further without it: the LP may
  // be unbounded, or the bound decided the vertex. Either way this is not the LP's answer.
  for (int32_t v : at_artificial_bound_) {
    if (status_[v] == VarStatus::kAtUpper && !IsFinite(upper_[v])) return false;
  }
  at_artificial_bound_.clear();
  return true;
}

// ---------------------------------------------------------------------------------------------
// Basis and factorization

void SparseDualSimplex::ResetToSlackBasis() {
  at_artificial_bound_.clear();
  std::fill(edge_weight_.begin(), edge_weight_.end(), 1.0);
  for (int j = 0; j < num_columns_; ++j) {
    status_[j] = VarStatus::kAtLower;
    position_[j] = -1;
    reduced_cost_[j] = cost_[j];
  }
  for (int v = num_columns_; v < num_variables(); ++v) status_[v] = VarStatus::kBasic;
  factorization_valid_ = false;
  for (int j = 0; j < num_columns_; ++j) PlaceNonbasic(j);
}

void SparseDualSimplex::AdoptBasis(std::span<const uint8_t> is_basic,
                                   std::span<const double> column_values) {
  ISPQ_RELEASE_INVARIANT(is_basic.size() == static_cast<size_t>(num_variables()),
                         "one basis flag per column and row");
  ISPQ_RELEASE_INVARIANT(column_values.size() == static_cast<size_t>(num_columns_),
                         "one value per column");
  at_artificial_bound_.clear();
  std::fill(edge_weight_.begin(), edge_weight_.end(), 1.0);
  factorization_valid_ = false;  // so that the moves below only record the values
  for (int v = 0; v < num_variables(); ++v) {
    position_[v] = -1;
    if (is_basic[v]) {
      status_[v] = VarStatus::kBasic;
      continue;
    }
    double x = 0;  // a logical's value is its row's activity
    if (IsLogical(v)) {
      const int row = v - num_columns_;
      for (int32_t t = row_start_[row]; t < row_start_[row + 1]; ++t) {
        x += row_coef_[t] * column_values[row_column_[t]];
      }
    } else {
      x = column_values[v];
    }
    const double l = lower_[v], u = upper_[v];
    const bool at_lower = IsFinite(l) && (!IsFinite(u) || std::abs(x - l) <= std::abs(x - u));
    if (at_lower) {
      status_[v] = VarStatus::kAtLower;
      MoveNonbasicTo(v, l);
    } else if (IsFinite(u)) {
      status_[v] = VarStatus::kAtUpper;
      MoveNonbasicTo(v, u);
    } else {
      status_[v] = VarStatus::kFree;
      MoveNonbasicTo(v, 0);
    }
  }
  costs_changed_ = 0;  // the adopted basis is optimal for these costs
}

bool SparseDualSimplex::Refactorize() {
  ++refactorizations_;
  work_done_ += num_rows_;
  factorization_valid_ = false;
  const int m = num_rows_;
  const int capacity = m + options_.max_pivots + 16;
  for (CoinIndexedVector* v :
       {work_.get(), column_.get(), row_.get(), pending_primal_.get(), pending_cost_.get()}) {
    v->clear();
    if (v->capacity() < capacity) v->reserve(capacity);
  }
  has_pending_primal_ = has_pending_cost_ = false;
  basic_variable_.assign(m, -1);
  is_primal_candidate_.assign(m, 0);
  primal_candidates_.clear();
  leaving_heap_.clear();
  leaving_stamp_.assign(m, 0);
  if (m == 0) {
    for (int j = 0; j < num_columns_; ++j) {
      reduced_cost_[j] = status_[j] == VarStatus::kBasic ? 0 : cost_[j];
    }
    factorization_valid_ = true;
    return true;
  }
  auto& [basics, rows, columns, permutation, elements] = basis_triplets_;
  basics.clear();
  rows.clear();
  columns.clear();
  elements.clear();
  for (int v = 0; v < num_variables(); ++v) {
    if (status_[v] != VarStatus::kBasic) continue;
    const int k = static_cast<int>(basics.size());
    basics.push_back(v);
    if (IsLogical(v)) {
      rows.push_back(v - num_columns_);
      columns.push_back(k);
      elements.push_back(-1);
    } else {
      for (int32_t t = column_start_[v]; t < column_start_[v + 1]; ++t) {
        rows.push_back(column_row_[t]);
        columns.push_back(k);
        elements.push_back(column_coef_[t]);
      }
    }
  }
  if (static_cast<int>(basics.size()) != m) return false;
  factorization_->maximumPivots(options_.max_pivots);
  permutation.resize(m);
  const int size = static_cast<int>(elements.size());
  // Room for the factors plus what max_pivots updates can add before the next refactorization
  // (a column of U and a row eta of at most m entries each), at most 8000 entries. A fixed 8000
  // gave every LP about 430 KB of areas, most of the heap of a mesh of many small subproblems;
  // the updates never need more than this bound, so no refactorization comes earlier.
  const int update_room = static_cast<int>(
      std::min<int64_t>(8000, static_cast<int64_t>(options_.max_pivots) * (m + 1)));
  const int area = m + 2 * size + update_room;
  int status = -99;
  for (double area_factor = 1; status == -99 && area_factor <= 64; area_factor *= 2) {
    status = factorization_->factorize(m, m, size, area, 2 * area, rows.data(), columns.data(),
                                       elements.data(), permutation.data(), area_factor);
  }
  if (status != 0) return false;
  factorization_->sparseThreshold(0);
  factorization_->goSparse();
  factorization_->checkSparse();
  for (int k = 0; k < m; ++k) {
    basic_variable_[permutation[k]] = basics[k];
    position_[basics[k]] = permutation[k];
  }
  if constexpr (kCheckInvariants) CheckBasisInvariants();
  factorization_valid_ = true;
  RecomputePrimalValues();
  RecomputeReducedCosts();
  for (int position = 0; position < m; ++position) MarkPrimalCandidate(position);
  return true;
}

void SparseDualSimplex::RecomputePrimalValues() {
  // x_B = -B^-1 (N x_N), over the nonbasic variables away from zero; the lists of nonzero
  // values are rebuilt on the way.
  nonzero_nonbasic_.clear();
  is_nonzero_nonbasic_.assign(num_variables(), 0);
  for (int v = 0; v < num_variables(); ++v) {
    if (status_[v] != VarStatus::kBasic && value_[v] != 0) {
      AddColumnTo(v, value_[v], column_.get());
      NoteNonbasicValue(v);
    }
  }
  factorization_->updateColumn(work_.get(), column_.get());
  const double* w = column_->denseVector();
  nonzero_basic_.clear();
  is_nonzero_basic_.assign(num_rows_, 0);
  for (int position = 0; position < num_rows_; ++position) {
    value_[basic_variable_[position]] = std::abs(w[position]) < kNoise ? 0 : -w[position];
    NoteBasicValue(position);
  }
  column_->clear();
}

void SparseDualSimplex::RecomputeBasicValues() {
  // The same as RecomputePrimalValues over the kept lists: work proportional to the nonzero
  // values, not to the model.
  size_t kept = 0;
  for (int32_t v : nonzero_nonbasic_) {
    if (status_[v] == VarStatus::kBasic || value_[v] == 0) {
      is_nonzero_nonbasic_[v] = 0;
      continue;
    }
    nonzero_nonbasic_[kept++] = v;
    AddColumnTo(v, value_[v], column_.get());
  }
  nonzero_nonbasic_.resize(kept);
  factorization_->updateColumn(work_.get(), column_.get());
  const double* w = column_->denseVector();
  for (int32_t position : nonzero_basic_) {
    is_nonzero_basic_[position] = 0;
    double& value = value_[basic_variable_[position]];
    if (w[position] == 0 && value != 0) {
      value = 0;
      MarkPrimalCandidate(position);
    }
  }
  nonzero_basic_.clear();
  const int* index = column_->getIndices();
  for (int k = 0; k < column_->getNumElements(); ++k) {
    const int position = index[k];
    double& value = value_[basic_variable_[position]];
    const double fresh = std::abs(w[position]) < kNoise ? 0 : -w[position];
    if (fresh != value) {
      value = fresh;
      MarkPrimalCandidate(position);
    }
    NoteBasicValue(position);
  }
  column_->clear();
}

void SparseDualSimplex::AppendNonzeroColumns(std::vector<int32_t>* columns) const {
  for (int32_t position : nonzero_basic_) {
    const int v = basic_variable_[position];
    if (!IsLogical(v) && value_[v] != 0) columns->push_back(v);
  }
  for (int32_t v : nonzero_nonbasic_) {
    if (!IsLogical(v) && status_[v] != VarStatus::kBasic && value_[v] != 0) columns->push_back(v);
  }
}

void SparseDualSimplex::NoteBasicValue(int position) {
  if (is_nonzero_basic_[position] || value_[basic_variable_[position]] == 0) return;
  is_nonzero_basic_[position] = 1;
  nonzero_basic_.push_back(position);
}

void SparseDualSimplex::NoteNonbasicValue(int v) {
  if (is_nonzero_nonbasic_[v] || value_[v] == 0) return;
  is_nonzero_nonbasic_[v] = 1;
  nonzero_nonbasic_.push_back(v);
}

void SparseDualSimplex::RecomputeReducedCosts() {
  // y = B^-T c_B, then d_v = c_v - col_v^T y for every variable (0 for the basic ones).
  for (int position = 0; position < num_rows_; ++position) {
    const double c = cost_[basic_variable_[position]];
    if (c != 0) row_->quickAdd(position, c);
  }
  factorization_->updateColumnTranspose(work_.get(), row_.get());
  const double* y = row_->denseVector();
  for (int j = 0; j < num_columns_; ++j) {
    double d = cost_[j];
    for (int32_t t = column_start_[j]; t < column_start_[j + 1]; ++t) {
      d -= column_coef_[t] * y[column_row_[t]];
    }
    reduced_cost_[j] = status_[j] == VarStatus::kBasic ? 0 : d;
  }
  for (int i = 0; i < num_rows_; ++i) {
    const int v = num_columns_ + i;
    reduced_cost_[v] = status_[v] == VarStatus::kBasic ? 0 : y[i];
  }
  row_->clear();
}

SparseDualSimplex::ScratchCheck SparseDualSimplex::CheckAgainstScratch() {
  ScratchCheck check;
  if (!factorization_valid_) return check;
  const std::vector<double> values = value_, reduced_costs = reduced_cost_;
  const std::vector<int32_t> nonzero_basic = nonzero_basic_, nonzero_nonbasic = nonzero_nonbasic_;
  const std::vector<uint8_t> is_nonzero_basic = is_nonzero_basic_,
                             is_nonzero_nonbasic = is_nonzero_nonbasic_;
  RecomputePrimalValues();
  RecomputeReducedCosts();
  for (int v = 0; v < num_variables(); ++v) {
    check.value_drift = std::max(check.value_drift, std::abs(values[v] - value_[v]));
    if (status_[v] == VarStatus::kBasic) {
      check.primal_infeasibility = std::max(check.primal_infeasibility, Infeasibility(v));
    } else if (DualInfeasible(v)) {
      ++check.dual_infeasible;
    }
  }
  value_ = values;
  reduced_cost_ = reduced_costs;
  nonzero_basic_ = nonzero_basic;
  nonzero_nonbasic_ = nonzero_nonbasic;
  is_nonzero_basic_ = is_nonzero_basic;
  is_nonzero_nonbasic_ = is_nonzero_nonbasic;
  return check;
}

// ---------------------------------------------------------------------------------------------
// Iterations

double SparseDualSimplex::Infeasibility(int v) const {
  const double x = value_[v];
  if (x < lower_[v] - options_.primal_tolerance) return lower_[v] - x;
  if (x > upper_[v] + options_.primal_tolerance) return x - upper_[v];
  return 0;
}

void SparseDualSimplex::MarkPrimalCandidate(int position) {
  if (is_primal_candidate_[position]) return;
  is_primal_candidate_[position] = 1;
  primal_candidates_.push_back(position);
}

int SparseDualSimplex::ChooseLeavingPosition() {
  // Approximate steepest edge: the largest infeasibility^2 / weight, ties to the smaller variable.
  // Only the positions that changed since the last choice are scored again, into a heap: a
  // large LP has thousands of infeasible rows, and scanning them all for every pivot was a sixth
  // of a 100k-arc solve. Feasible positions leave the heap.
  const auto lower_priority = [](const LeavingCandidate& a, const LeavingCandidate& b) {
    return a.score < b.score || (a.score == b.score && a.variable > b.variable);
  };
  for (const int position : primal_candidates_) {
    is_primal_candidate_[position] = 0;
    const uint32_t stamp = ++leaving_stamp_[position];
    const int v = basic_variable_[position];
    const double infeasibility = Infeasibility(v);
    if (infeasibility == 0) {
      // Feasible: a value within the tolerance of a bound is put on it, so that the rounding
      // of the updates does not show in the answer (1e-10 on a column of weight 1e8 is 0.01).
      if (std::abs(value_[v] - lower_[v]) <= options_.primal_tolerance) value_[v] = lower_[v];
      if (std::abs(value_[v] - upper_[v]) <= options_.primal_tolerance) value_[v] = upper_[v];
      continue;
    }
    leaving_heap_.push_back({infeasibility * infeasibility / edge_weight_[v], v, position, stamp});
    std::push_heap(leaving_heap_.begin(), leaving_heap_.end(), lower_priority);
  }
  primal_candidates_.clear();
  if (leaving_heap_.size() > 4 * static_cast<size_t>(num_rows_) + 64) {
    // Mostly stale entries: keep the current ones only.
    std::erase_if(leaving_heap_, [this](const LeavingCandidate& c) {
      return c.stamp != leaving_stamp_[c.position];
    });
    std::make_heap(leaving_heap_.begin(), leaving_heap_.end(), lower_priority);
  }
  while (!leaving_heap_.empty() &&
         leaving_heap_.front().stamp != leaving_stamp_[leaving_heap_.front().position]) {
    std::pop_heap(leaving_heap_.begin(), leaving_heap_.end(), lower_priority);
    leaving_heap_.pop_back();
  }
  return leaving_heap_.empty() ? -1 : leaving_heap_.front().position;
}

void SparseDualSimplex::ComputePivotRow(int position) {
  // rho = B^-T e_position; alpha_v = rho^T col_v for the nonbasic variables in reach.
  row_->clear();
  row_->insert(position, 1.0);
  factorization_->updateColumnTranspose(work_.get(), row_.get());
  ForEachNonbasicShare(*row_, [this](int v, double share) {
    if (alpha_[v] == 0) alpha_touched_.push_back(v);
    alpha_[v] += share;
    if (alpha_[v] == 0) alpha_[v] = 1e-300;  // keep it marked as touched
  });
}

bool SparseDualSimplex::RefreshLeavingValue(int position) {
  // The leaving variable's value from scratch: x_p = -rho^T N x_N, and rho^T col_v is the pivot
  // row entry alpha_v. Incremental updates drift by rounding (with weights of 1e9 next to 0.1),
  // and a drifted value must neither start a pivot nor prove the LP infeasible.
  const int leaving = basic_variable_[position];
  double value = 0;
  for (int32_t v : alpha_touched_) value -= alpha_[v] * value_[v];
  value_[leaving] = value;
  NoteBasicValue(position);
  MarkPrimalCandidate(position);  // scored again at the next choice
  if (Infeasibility(leaving) > 0) return true;
  for (int32_t v : alpha_touched_) alpha_[v] = 0;
  alpha_touched_.clear();
  row_->clear();
  return false;
}

int SparseDualSimplex::ChooseEntering(int direction, double* dual_step) {
  // With the leaving variable below its lower bound (direction +1) the duals move as
  // d_v + t * alpha_v, above its upper bound (-1) as d_v - t * alpha_v, t >= 0; the entering
  // variable is the first whose reduced cost reaches zero. Harris' two passes: the bound on t
  // with every reduced cost allowed to go a tolerance past zero, then the largest |alpha| among
  // the candidates within it (a stable pivot).
  double bound = kInf;
  for (int32_t v : alpha_touched_) {
    const double a = direction * alpha_[v];
    if (std::abs(a) < options_.pivot_tolerance || lower_[v] == upper_[v]) continue;
    const double d = reduced_cost_[v], tol = DualTolerance(v);
    switch (status_[v]) {
      case VarStatus::kAtLower:
        if (a < 0) bound = std::min(bound, (d + tol) / -a);
        break;
      case VarStatus::kAtUpper:
        if (a > 0) bound = std::min(bound, (-d + tol) / a);
        break;
      case VarStatus::kFree:
        bound = std::min(bound, tol / std::abs(a));
        break;
      case VarStatus::kBasic:
        break;
    }
  }
  if (!IsFinite(bound)) return -1;
  int entering = -1;
  double best_alpha = 0, step = 0;
  for (int32_t v : alpha_touched_) {
    const double a = direction * alpha_[v];
    if (std::abs(a) < options_.pivot_tolerance || lower_[v] == upper_[v]) continue;
    const double d = reduced_cost_[v];
    double ratio;
    if (status_[v] == VarStatus::kAtLower && a < 0) {
      ratio = std::max(d, 0.0) / -a;
    } else if (status_[v] == VarStatus::kAtUpper && a > 0) {
      ratio = std::max(-d, 0.0) / a;
    } else if (status_[v] == VarStatus::kFree) {
      ratio = 0;
    } else {
      continue;
    }
    if (ratio > bound) continue;
    if (std::abs(a) > best_alpha || (std::abs(a) == best_alpha && v < entering)) {
      best_alpha = std::abs(a);
      entering = v;
      step = ratio;
    }
  }
  *dual_step = step;
  return entering;
}

bool SparseDualSimplex::Pivot(int position, int entering, int direction, double dual_step) {
  const int leaving = basic_variable_[position];
  ISPQ_INVARIANT(status_[entering] != VarStatus::kBasic, "the entering variable is nonbasic");
  ISPQ_INVARIANT(position_[leaving] == position, "the leaving variable sits at its position");
  ISPQ_INVARIANT(dual_step >= 0, "a dual simplex step never lowers the objective");
  // The leaving row's exact steepest-edge weight |rho|^2 (rho is at hand).
  double rho_norm = 0;
  {
    const double* rho = row_->denseVector();
    const int* index = row_->getIndices();
    for (int k = 0; k < row_->getNumElements(); ++k) {
      const double r = rho[index[k]];
      if (std::abs(r) >= kNoise) rho_norm += r * r;
    }
  }
  column_->clear();
  AddColumnTo(entering, 1.0, column_.get());
  factorization_->setCollectStatistics(true);
  factorization_->updateColumnFT(work_.get(), column_.get());
  factorization_->setCollectStatistics(false);
  work_done_ += row_->getNumElements() + column_->getNumElements();
  const double* w = column_->denseVector();
  const double pivot = w[position];
  const double alpha = alpha_[entering];
  if (std::abs(pivot - alpha) > kPivotAgreement * (1 + std::abs(pivot))) {
    work_->clear();
    column_->clear();
    return false;
  }
  // Primal: the leaving variable goes to its violated bound, the entering one moves by theta.
  const double target = direction > 0 ? lower_[leaving] : upper_[leaving];
  const double theta = (value_[leaving] - target) / pivot;
  const int* index = column_->getIndices();
  for (int k = 0; k < column_->getNumElements(); ++k) {
    const int p = index[k];
    if (w[p] == 0) continue;
    value_[basic_variable_[p]] -= w[p] * theta;
    NoteBasicValue(p);
    MarkPrimalCandidate(p);
    if (p != position) {
      // Devex: a row's weight only grows, by the part of the leaving row's it takes over.
      const double ratio = w[p] / pivot;
      double& weight = edge_weight_[basic_variable_[p]];
      weight = std::max(weight, ratio * ratio * rho_norm);
    }
  }
  edge_weight_[entering] = std::max(rho_norm / (pivot * pivot), 1.0);
  value_[entering] += theta;
  value_[leaving] = target;
  NoteNonbasicValue(leaving);
  // Dual: d_v += direction * t * alpha_v along the pivot row; the leaving variable's reduced cost
  // becomes direction * t (>= 0 at its lower bound, <= 0 at its upper one).
  for (int32_t v : alpha_touched_) reduced_cost_[v] += direction * dual_step * alpha_[v];
  reduced_cost_[entering] = 0;
  reduced_cost_[leaving] = direction * dual_step;
  // Basis.
  const int update = factorization_->replaceColumn(work_.get(), position, pivot);
  work_->clear();
  column_->clear();
  status_[leaving] = direction > 0 ? VarStatus::kAtLower : VarStatus::kAtUpper;
  if (lower_[leaving] == upper_[leaving]) status_[leaving] = VarStatus::kAtLower;
  position_[leaving] = -1;
  status_[entering] = VarStatus::kBasic;
  position_[entering] = position;
  basic_variable_[position] = entering;
  NoteBasicValue(position);
  MarkPrimalCandidate(position);
  if (update >= 2) factorization_valid_ = false;  // singular or out of room: rebuild
  return true;
}

void SparseDualSimplex::CheckBasisInvariants() const {
  int basic = 0;
  for (int v = 0; v < num_variables(); ++v) {
    if (status_[v] != VarStatus::kBasic) continue;
    ++basic;
    ISPQ_INVARIANT(position_[v] >= 0 && position_[v] < num_rows_, "a basic variable has a row");
    ISPQ_INVARIANT(basic_variable_[position_[v]] == v, "position and basis agree");
  }
  ISPQ_INVARIANT(basic == num_rows_, "the basis is square");
}

void SparseDualSimplex::CheckOptimalInvariants() const {
  // The answer is primal feasible within the tolerance the leaving row's choice uses, and every
  // nonbasic variable sits on a bound (or at 0 when it has none).
  for (int v = 0; v < num_variables(); ++v) {
    if (status_[v] == VarStatus::kBasic) {
      ISPQ_INVARIANT(Infeasibility(v) <= 1e3 * options_.primal_tolerance,
                     "an optimal basis is primal feasible");
    } else {
      const double x = value_[v];
      ISPQ_INVARIANT(x == lower_[v] || x == upper_[v] || (status_[v] == VarStatus::kFree && x == 0),
                     "a nonbasic variable sits on a bound");
    }
  }
}

bool SparseDualSimplex::most_costs_changed() const {
  return costs_changed_ > std::max<int64_t>(100, num_columns_ / 10);
}

SparseDualSimplex::Status SparseDualSimplex::Solve(int64_t max_iterations, int64_t max_work) {
  if (max_iterations <= 0 || max_iterations > options_.max_iterations) {
    max_iterations = options_.max_iterations;
  }
  // A warm basis is worth keeping when a few costs changed. When most did (a new objective, such
  // as the sheet LP's switch between weight schemes), repairing its dual feasibility column by
  // column took thousands of pivots (1.8 s for one solve at 100k arcs).
  if (most_costs_changed()) ResetToSlackBasis();
  costs_changed_ = 0;
  const int64_t work_limit = max_work > 0 ? work_done_ + max_work : 0;
  int64_t iterations = 0;
  int trouble = 0;
  bool reset = false;
  bool values_exact = false;
  int drops_since_pivot = 0;
  int64_t degenerate_run = 0;  // pivots in a row that left the objective where it was
  for (int64_t pass = 1;; ++pass) {
    // Every pass either pivots or does a pivot's worth of work (a pivot row, a refactorization).
    if (pass % kPassesBetweenStopChecks == 0 && should_stop_ && should_stop_()) {
      return Status::kStopped;
    }
    if (!factorization_valid_ || factorization_->pivots() >= options_.max_pivots) {
      dual_check_.clear();
      if (!Refactorize()) {
        ResetToSlackBasis();
        if (!Refactorize()) return Status::kFailed;
      }
      // Every reduced cost was recomputed: check them all.
      for (int v = 0; v < num_variables(); ++v) {
        if (status_[v] != VarStatus::kBasic && DualInfeasible(v)) dual_check_.push_back(v);
      }
    }
    ApplyPendingCostChange();
    if (!RepairDualFeasibility()) {
      if (reset) return Status::kFailed;  // not even the slack basis is dual feasible
      reset = true;
      ResetToSlackBasis();
      continue;
    }
    ApplyPendingPrimalChange();
    const int position = ChooseLeavingPosition();
    if (position < 0) {
      // Feasible as far as the kept values tell; the exact ones decide (and are the answer).
      if (!values_exact) {
        RecomputeBasicValues();
        values_exact = true;
        continue;
      }
      if (!LeftArtificialBounds()) return Status::kFailed;
      if constexpr (kCheckInvariants) CheckOptimalInvariants();
      return Status::kOptimal;
    }
    if (++iterations > max_iterations) return Status::kFailed;
    if (work_limit > 0 && work_done_ > work_limit) return Status::kFailed;
    ComputePivotRow(position);
    if (!RefreshLeavingValue(position)) {
      // It was only rounding. A refreshed value is as exact as a recomputed one, so the flag
      // stands: were it cleared here, the recomputation (FTRAN) and the refresh (BTRAN), which
      // can disagree by more than the tolerance on the same value, would take turns until the
      // iteration limit (200,000 dropped candidates and no pivot in one solve at 200k arcs).
      // Many drops since the last pivot mean the kept values drifted: recomputing them all at
      // once is cheaper than one pivot row per drifted value.
      if (!values_exact && ++drops_since_pivot >= kDropsBeforeRecompute) {
        RecomputeBasicValues();
        values_exact = true;
      }
      continue;
    }
    values_exact = false;
    drops_since_pivot = 0;
    const int leaving = basic_variable_[position];
    const int direction = value_[leaving] < lower_[leaving] ? 1 : -1;
    double dual_step = 0;
    const int entering = ChooseEntering(direction, &dual_step);
    bool pivoted = false;
    if (entering >= 0) pivoted = Pivot(position, entering, direction, dual_step);
    work_done_ += static_cast<int64_t>(alpha_touched_.size());
    row_->clear();
    for (int32_t v : alpha_touched_) alpha_[v] = 0;
    alpha_touched_.clear();
    // No entering candidate: the pivot row proves the LP infeasible.
    if (entering < 0) return Status::kInfeasible;
    if (!pivoted) {
      if (++trouble > 10) return Status::kFailed;
      factorization_valid_ = false;
      continue;
    }
    ++iterations_;
    if (dual_step > 0) {
      degenerate_run = 0;
    } else {
      ++degenerate_pivots_;
      if (++degenerate_run > options_.max_degenerate_pivots) {
        ++stalled_solves_;
        return Status::kFailed;
      }
    }
  }
}

}  // namespace ispq
