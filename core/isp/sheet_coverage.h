// SPDX-License-Identifier: Apache-2.0
// The (bundle, direction) checks of the greedy passes that a non-improving sheet already answered
// (core/README.md, section Covered checks).
//
// An integer sheet is a dual surface: the cheapest sheet through one root usually is the cheapest
// sheet through every other bundle it moves, in the direction it moves them. When the cheapest
// sheet of a root does not improve the objective (in a thorough pass: nor its repair), a greedy
// pass on a large subproblem takes it as the answer for those bundles too instead of solving
// their LPs (paper Alg. 2 checks each root; this is the shortcut of
// IspTuning::cover_min_bundles). Any applied sheet changes the weights and any new row the
// feasible sheets, so either clears the coverage.
#ifndef ISPQ_CORE_ISP_SHEET_COVERAGE_H_
#define ISPQ_CORE_ISP_SHEET_COVERAGE_H_

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/arc_bundles.h"
#include "core/isp/integer_sheet.h"

namespace ispq {

class SheetCoverage {
 public:
  explicit SheetCoverage(int num_bundles);

  // Every bundle of `sheet` counts as answered in the direction the sheet moves it.
  void Cover(const IntegerSheet& sheet);
  // Forgets every sheet (the quantization changed).
  void Clear();
  struct Answer {
    std::span<const BundleId> bundles;  // of the sheet that answered
    uint64_t id;                        // the sheet's, unique in the run
  };
  // The sheet that answered (b, inflate), if one did.
  std::optional<Answer> CoveringSheet(BundleId b, bool inflate) const;

 private:
  static size_t Key(BundleId b, bool inflate) { return 2 * static_cast<size_t>(b) + inflate; }

  // Per (bundle, direction): the generation and the index of the sheet that covered it.
  std::vector<uint32_t> generation_;
  std::vector<int32_t> sheet_index_;
  uint32_t current_ = 1;
  std::vector<std::vector<BundleId>> sheets_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_COVERAGE_H_
