// SPDX-License-Identifier: Apache-2.0
// An integer sheet: a consistency-preserving integer update of the bundle lengths (paper section
// 4.2), stored sparsely over the bundles it changes. Positive entries inflate, negative ones
// deflate; a sheet with both is a mixed-sign sheet (section 4.3.3). See core/README.md, section
// Integer sheets.
#ifndef ISPQ_CORE_ISP_INTEGER_SHEET_H_
#define ISPQ_CORE_ISP_INTEGER_SHEET_H_

#include <cstdint>
#include <vector>

#include "core/arc_bundles.h"

namespace ispq {

struct IntegerSheet {
  std::vector<BundleId> bundles;  // ascending, each once
  std::vector<int64_t> deltas;    // non-zero, parallel to bundles
  int64_t lcd = 1;                // the denominator the LP solution was scaled by

  bool empty() const { return bundles.empty(); }
  void Clear() {
    bundles.clear();
    deltas.clear();
    lcd = 1;
  }
};

enum class SheetSign : uint8_t { kInflating, kDeflating, kMixed };

inline SheetSign SignOfSheet(const IntegerSheet& sheet) {
  bool positive = false, negative = false;
  for (int64_t d : sheet.deltas) (d > 0 ? positive : negative) = true;
  if (positive && negative) return SheetSign::kMixed;
  return negative ? SheetSign::kDeflating : SheetSign::kInflating;
}

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_INTEGER_SHEET_H_
