// SPDX-License-Identifier: Apache-2.0
// A mixed-integer linear program in the plain form the exact mode hands to its solvers: columns
// with bounds, objective coefficients and integrality flags, and rows in the compressed form of
// core/lp_row_batch.h. The quantization model (core/exact/quantization_milp.h) builds one; the
// CBC back end solves it as a MILP and the CLP back end solves its LP relaxation, so that neither
// solver appears in the code that decides what the model is.
#ifndef ISPQ_CORE_EXACT_MILP_MODEL_H_
#define ISPQ_CORE_EXACT_MILP_MODEL_H_

#include <cstdint>
#include <vector>

#include "core/lp_row_batch.h"

namespace ispq {

struct MilpModel {
  // Minimize objective_offset + sum_j objective[j] * x_j over the columns' bounds and the rows.
  std::vector<double> column_lower;
  std::vector<double> column_upper;
  std::vector<double> objective;
  std::vector<uint8_t> integer;  // per column: 1 if x_j must be integral
  LpRowBatch rows;
  double objective_offset = 0;

  int num_columns() const { return static_cast<int>(objective.size()); }

  // Appends a column and returns its index.
  int AddColumn(double lower, double upper, double cost, bool is_integer) {
    column_lower.push_back(lower);
    column_upper.push_back(upper);
    objective.push_back(cost);
    integer.push_back(is_integer ? 1 : 0);
    return num_columns() - 1;
  }
};

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_MILP_MODEL_H_
