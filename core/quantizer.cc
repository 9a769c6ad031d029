#include "core/quantizer.h"

#include <chrono>
#include <cmath>
#include <optional>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/block_extents.h"
#include "core/isp/clp_sheet_lp.h"
#include "core/isp/integer_sheet_pump.h"
#include "core/quantization_limits.h"
#include "core/quantization_validator.h"

namespace ispq {

absl::Status ValidateQuantizeOptions(const TMesh& mesh, const QuantizeOptions& options) {
  if (!std::isfinite(options.scaling) || options.scaling <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("scaling must be finite and > 0, got ", options.scaling));
  }
  if (std::isnan(options.time_limit_seconds) || options.time_limit_seconds < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("time_limit_seconds must be >= 0, got ", options.time_limit_seconds));
  }
  return CheckTargetsRepresentable(mesh, options.scaling);
}

absl::StatusOr<QuantizeResult> Quantize(const TMesh& mesh, const QuantizeOptions& options,
                                        ProgressObserver* observer,
                                        const SolveInterrupter* interrupter) {
  const auto start = std::chrono::steady_clock::now();
  if (absl::Status valid = ValidateQuantizeOptions(mesh, options); !valid.ok()) return valid;

  absl::StatusOr<IspOutcome> outcome =
      RunIntegerSheetPump(mesh, options, ClpSheetLpFactory(), IspTuning{}, observer, interrupter);
  if (!outcome.ok()) return outcome.status();

  // Every result is checked by the validator, independently of what the algorithm believes.
  ValidationOptions validation;
  validation.separation = options.separation;
  if (options.per_arc_nonnegative) validation.per_arc_lower_bound = 0;
  absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, outcome->q, validation);
  if (!report.ok()) return report.status();

  if (!report->out_of_range.empty() || report->hexes_overflow) {
    // Never hand out a value that the API's int32 q or int64 hex count would wrap.
    return absl::InternalError(
        absl::StrCat("the quantization left the representable range: ", report->Describe(3)));
  }
  QuantizeResult result;
  result.termination = outcome->termination;
  result.valid = report->valid();
  if (!result.valid && outcome->separating) {
    return absl::InternalError(absl::StrCat(
        "the quantizer's final q passed its own separation checks but not the validator: ",
        report->Describe(5)));
  }
  if (!result.valid && result.termination == Termination::kConverged) {
    return absl::InternalError(
        absl::StrCat("the quantizer converged to an invalid q: ", report->Describe(5)));
  }
  result.q = std::move(outcome->q);
  double objective = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const double d = static_cast<double>(result.q[a]) - options.scaling * mesh.arc_length(a);
    objective += d * d;
  }
  result.objective = objective;
  result.hexes = result.valid ? *HexCount(mesh, result.q) : 0;
  result.stats = outcome->stats;
  result.stats.solve_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace ispq
