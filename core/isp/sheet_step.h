// SPDX-License-Identifier: Apache-2.0
// One step of the pump (paper Alg. 2 and 3): the rational vertex of a subproblem's sheet LP made
// into an integer sheet, checked against the active rows, with its best integer multiplicity along
// the convex objective (core/README.md, section From a rational vertex to an integer step).
//
// A rational vertex becomes integer by a dive (fix the fractional bundle closest to its next
// integer away from zero, re-solve, at most kMaxDivePins times) and then multiplication by the
// least common denominator of what is still fractional (section 4.3.1). The scaled sheet must
// keep every active row satisfied ("if Delta q violates (7c) or (7d)"); the rows also cap its
// multiplicity t, and OPTIMALINTEGERSTEP picks t at the vertex of the objective along the sheet.
#ifndef ISPQ_CORE_ISP_SHEET_STEP_H_
#define ISPQ_CORE_ISP_SHEET_STEP_H_

#include <cstdint>
#include <optional>
#include <vector>

#include "absl/status/statusor.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/integer_sheet.h"
#include "core/isp/isp_tuning.h"
#include "core/isp/sheet_subproblem.h"
#include "core/quantize_result.h"
#include "core/run_clock.h"

namespace ispq {

// An integer sheet, its multiplicity and the objective change of applying it that often.
struct SheetStep {
  IntegerSheet sheet;
  int64_t t = 0;
  double gain = 0;
};

class SheetStepFinder {
 public:
  // A dive pins at most this many bundles; a vertex still fractional then is lcd-scaled.
  static constexpr int kMaxDivePins = 2;

  // Everything referenced must outlive the finder. LP solves and denominators (paper Fig. 8)
  // are counted into `stats`.
  SheetStepFinder(const BundleQuantization& quantization, const InequalityRows& rows,
                  const IspTuning& tuning, RunClock& clock, QuantizeStats& stats);

  // false if the run must stop, the LP is infeasible or its vertex gives no sheet that the
  // consistency and the active rows accept; `step` is filled otherwise.
  absl::StatusOr<bool> Find(SheetSubproblem& subproblem, const SheetRequest& request,
                            SheetStep* step);

 private:
  absl::StatusOr<bool> SolveRational(SheetSubproblem& subproblem, const SheetRequest& request);
  absl::Status DiveToInteger(SheetSubproblem& subproblem, const SheetRequest& request);
  // Fills `sheet` with rational_ times its lcd; false if nothing is left.
  bool ScaleToInteger(IntegerSheet* sheet) const;
  // Whether every active row holds after one step; lowers *t_max to what they allow.
  bool RowsAllowStep(const IntegerSheet& sheet, int64_t* t_max);
  void PickMultiplicity(int64_t t_max, SheetStep* step) const;

  const BundleQuantization& quantization_;
  const InequalityRows& rows_;
  const IspTuning& tuning_;
  RunClock& clock_;
  QuantizeStats& stats_;

  RationalSheet rational_;
  std::optional<int64_t> lcd_;  // of rational_
  // Scratch of RowsAllowStep, per row.
  std::vector<int64_t> row_delta_;
  std::vector<uint8_t> row_touched_;
  std::vector<int32_t> touched_rows_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SHEET_STEP_H_
