// SPDX-License-Identifier: Apache-2.0
#include "client/validate_command.h"

#include <iostream>

#include "absl/strings/str_split.h"
#include "client/exit_codes.h"
#include "client/mesh_file_input.h"
#include "client/message_json.h"
#include "client/result_output.h"
#include "core/block_extents.h"
#include "core/proto/quantization_proto.h"
#include "core/quantization_objective.h"
#include "core/quantization_validator.h"
#include "core/scaling.h"

namespace ispq::cli {

int RunValidate(const ValidateCommandOptions& options) {
  const absl::StatusOr<TMesh> loaded = LoadMeshModel(options.mesh_path);
  if (!loaded.ok()) {
    std::cerr << "ispq: " << loaded.status().message() << "\n";
    return kExitInvalidInput;
  }
  const TMesh* mesh = &*loaded;
  absl::StatusOr<v1::QuantizationResult> result = ReadResultFile(options.result_path);
  if (!result.ok()) {
    std::cerr << "ispq: " << result.status().message() << "\n";
    return kExitInvalidInput;
  }
  absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(*result, *mesh);
  if (!q.ok()) {
    std::cerr << "ispq: " << options.result_path << ": " << q.status().message() << "\n";
    return kExitInvalidInput;
  }
  absl::StatusOr<double> scaling = ResolveScaling(ScalingChoiceFromProto(options.scaling), *mesh);
  if (!scaling.ok()) {
    std::cerr << "ispq: " << scaling.status().message() << "\n";
    return kExitUsage;
  }
  ValidationOptions validation;
  validation.separation = options.reference_block_boxes ? SeparationRule::kReferenceSearch
                                                        : SeparationRule::kBothSearches;
  absl::StatusOr<ValidationReport> report = ValidateQuantization(*mesh, *q, validation);
  if (!report.ok()) {
    std::cerr << "ispq: " << report.status().message() << "\n";
    return kExitFailed;
  }
  const double objective = QuantizationObjective(*mesh, *q, *scaling);
  const bool valid = report->valid();
  if (options.json) {
    v1::ValidationVerdict verdict;
    verdict.set_valid(valid);
    verdict.set_objective(objective);
    verdict.set_hexes(valid ? *HexCount(*mesh, *q) : 0);  // a valid q has a representable count
    verdict.set_consistency_violations(static_cast<int32_t>(report->consistency.size()));
    verdict.set_simple_violations(static_cast<int32_t>(report->simple.size()));
    verdict.set_separation_violations(static_cast<int32_t>(report->separation.size()));
    verdict.set_separation_checked(report->separation_checked);
    for (absl::string_view line : absl::StrSplit(report->Describe(), '\n', absl::SkipEmpty())) {
      verdict.add_problems(std::string(line));
    }
    std::cout << MessageToJson(verdict) << "\n";
  } else {
    std::cout << (valid ? "valid" : "NOT valid") << ": objective " << objective;
    if (valid) std::cout << ", " << *HexCount(*mesh, *q) << " hexes";
    std::cout << "\n";
    if (!valid) std::cout << report->Describe();
  }
  return valid ? kExitOk : kExitInvalidResult;
}

}  // namespace ispq::cli
