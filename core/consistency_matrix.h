// SPDX-License-Identifier: Apache-2.0
// The consistency matrix A of the quantization problem (paper eq. 1b; proto/README.md, section
// Consistency): one row per patch and in-plane axis, the sum of q over the side running along +axis
// minus the sum over the side running along -axis. A consistent q has A q = 0.
#ifndef ISPQ_CORE_CONSISTENCY_MATRIX_H_
#define ISPQ_CORE_CONSISTENCY_MATRIX_H_

#include <cstdint>
#include <span>
#include <vector>

#include "core/flat_lists.h"
#include "core/linear_terms.h"
#include "core/tmesh.h"

namespace ispq {

struct ConsistencyRowInfo {
  PatchId patch;
  int axis;  // the axis (0..2, in the patch's reference block frame) the two sides run along
};

class ConsistencyMatrix {
 public:
  explicit ConsistencyMatrix(const TMesh& mesh);

  int num_rows() const { return static_cast<int>(info_.size()); }
  const ConsistencyRowInfo& row_info(int r) const { return info_[r]; }
  std::span<const LinearTerm> row(int r) const { return terms_[r]; }

  // Value of row r for q (zero when q is consistent on that row).
  int64_t RowValue(int r, std::span<const int64_t> q) const;

 private:
  std::vector<ConsistencyRowInfo> info_;
  FlatLists<LinearTerm> terms_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_CONSISTENCY_MATRIX_H_
