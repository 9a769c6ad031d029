// SPDX-License-Identifier: Apache-2.0
// Rows of a linear program in compressed form, the one currency in which LP rows travel between
// the code that decides them and the code that solves them: the sheet LPs (core/isp/sheet_lp.h)
// take appended separation rows as a batch, and exact mode's MILP (core/exact/milp_model.h) keeps
// all its rows in one.
#ifndef ISPQ_CORE_LP_ROW_BATCH_H_
#define ISPQ_CORE_LP_ROW_BATCH_H_

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace ispq {

inline constexpr double kLpInfinity = std::numeric_limits<double>::infinity();

// A batch of rows in compressed form: row i consists of the terms [starts[i], starts[i + 1])
// and requires lower[i] <= sum coef * x <= upper[i] (either bound may be infinite).
class LpRowBatch {
 public:
  LpRowBatch() : starts_{0} {}

  void Add(std::span<const int32_t> columns, std::span<const double> coefs, double lower,
           double upper) {
    columns_.insert(columns_.end(), columns.begin(), columns.end());
    coefs_.insert(coefs_.end(), coefs.begin(), coefs.end());
    starts_.push_back(static_cast<int32_t>(columns_.size()));
    lower_.push_back(lower);
    upper_.push_back(upper);
  }
  void Clear() {
    starts_.assign(1, 0);
    columns_.clear();
    coefs_.clear();
    lower_.clear();
    upper_.clear();
  }

  int size() const { return static_cast<int>(lower_.size()); }
  std::span<const int32_t> starts() const { return starts_; }
  std::span<const int32_t> columns() const { return columns_; }
  std::span<const double> coefs() const { return coefs_; }
  std::span<const double> lower() const { return lower_; }
  std::span<const double> upper() const { return upper_; }

 private:
  std::vector<int32_t> starts_;
  std::vector<int32_t> columns_;
  std::vector<double> coefs_;
  std::vector<double> lower_, upper_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_LP_ROW_BATCH_H_
