// SPDX-License-Identifier: Apache-2.0
#include "tests/support/consistent_quantizations.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>

#include "core/consistency_matrix.h"

namespace ispq::testing {
namespace {

using SparseRow = std::vector<std::pair<ArcId, int64_t>>;  // sorted by arc, no zeros

int64_t Checked(__int128 value) {
  if (value > INT64_MAX || value < INT64_MIN) {
    std::fprintf(stderr, "ConsistentQuantizations: int64 overflow in the elimination\n");
    std::abort();
  }
  return static_cast<int64_t>(value);
}

int64_t CoefficientOf(const SparseRow& row, ArcId column) {
  const auto it = std::lower_bound(row.begin(), row.end(), std::make_pair(column, INT64_MIN));
  return it != row.end() && it->first == column ? it->second : 0;
}

// a * x - b * y, divided by the gcd of its coefficients.
SparseRow Combine(int64_t a, const SparseRow& x, int64_t b, const SparseRow& y) {
  SparseRow result;
  size_t i = 0, j = 0;
  while (i < x.size() || j < y.size()) {
    ArcId column;
    __int128 value = 0;
    if (j == y.size() || (i < x.size() && x[i].first < y[j].first)) {
      column = x[i].first;
      value = static_cast<__int128>(a) * x[i++].second;
    } else if (i == x.size() || y[j].first < x[i].first) {
      column = y[j].first;
      value = -static_cast<__int128>(b) * y[j++].second;
    } else {
      column = x[i].first;
      value = static_cast<__int128>(a) * x[i++].second - static_cast<__int128>(b) * y[j++].second;
    }
    if (value != 0) result.push_back({column, Checked(value)});
  }
  int64_t divisor = 0;
  for (const auto& [column, value] : result) divisor = std::gcd(divisor, value);
  if (divisor > 1) {
    for (auto& entry : result) entry.second /= divisor;
  }
  return result;
}

}  // namespace

ConsistentQuantizations::ConsistentQuantizations(const TMesh& mesh) : num_arcs_(mesh.num_arcs()) {
  lengths_.assign(mesh.arc_lengths().begin(), mesh.arc_lengths().end());
  const ConsistencyMatrix consistency(mesh);
  std::vector<SparseRow> pivot_rows;
  std::vector<ArcId> pivot_columns;
  std::vector<int> pivot_row_of(num_arcs_, -1);
  for (int r = 0; r < consistency.num_rows(); ++r) {
    SparseRow row;
    for (const LinearTerm& t : consistency.row(r)) row.push_back({t.var, t.coef});
    std::sort(row.begin(), row.end());
    row = Combine(1, row, 0, {});  // merges nothing, drops zeros, normalizes
    // Reduce by the existing pivots; each pivot row has no other pivot column, so one pass over
    // the pivot columns suffices.
    for (size_t k = 0; k < pivot_rows.size(); ++k) {
      const int64_t value = CoefficientOf(row, pivot_columns[k]);
      if (value == 0) continue;
      row = Combine(CoefficientOf(pivot_rows[k], pivot_columns[k]), row, value, pivot_rows[k]);
    }
    if (row.empty()) continue;
    // Pivot on the entry of smallest magnitude to keep numbers small.
    const auto pivot = std::min_element(row.begin(), row.end(), [](const auto& x, const auto& y) {
      return std::abs(x.second) < std::abs(y.second);
    });
    const ArcId column = pivot->first;
    const int64_t pivot_value = pivot->second;
    for (size_t k = 0; k < pivot_rows.size(); ++k) {
      const int64_t value = CoefficientOf(pivot_rows[k], column);
      if (value == 0) continue;
      pivot_rows[k] = Combine(pivot_value, pivot_rows[k], value, row);
    }
    pivot_row_of[column] = static_cast<int>(pivot_rows.size());
    pivot_rows.push_back(std::move(row));
    pivot_columns.push_back(column);
  }

  for (ArcId a = 0; a < num_arcs_; ++a) {
    if (pivot_row_of[a] < 0) free_arcs_.push_back(a);
  }
  for (size_t k = 0; k < pivot_rows.size(); ++k) {
    Determined d;
    d.arc = pivot_columns[k];
    d.pivot = CoefficientOf(pivot_rows[k], d.arc);
    for (const auto& [column, value] : pivot_rows[k]) {
      if (column != d.arc) d.free_terms.push_back({column, value});
    }
    multiplier_ = Checked(static_cast<__int128>(multiplier_) / std::gcd(multiplier_, d.pivot) *
                          std::abs(d.pivot));
    determined_.push_back(std::move(d));
  }
}

std::vector<int64_t> ConsistentQuantizations::Extend(std::span<const int64_t> free_values) const {
  std::vector<int64_t> q(num_arcs_, 0);
  for (size_t i = 0; i < free_arcs_.size(); ++i) {
    q[free_arcs_[i]] = Checked(static_cast<__int128>(multiplier_) * free_values[i]);
  }
  for (const Determined& d : determined_) {
    __int128 sum = 0;
    for (const auto& [column, value] : d.free_terms)
      sum += static_cast<__int128>(value) * q[column];
    q[d.arc] = Checked(-sum / d.pivot);
  }
  return q;
}

std::vector<int64_t> ConsistentQuantizations::NearTargets(double scale) const {
  std::vector<int64_t> free_values;
  for (ArcId a : free_arcs_) free_values.push_back(std::llround(scale * lengths_[a]));
  return Extend(free_values);
}

}  // namespace ispq::testing
