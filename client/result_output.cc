// SPDX-License-Identifier: Apache-2.0
#include "client/result_output.h"

#include <fstream>
#include <iostream>

#include "absl/strings/str_cat.h"
#include "client/exit_codes.h"
#include "client/message_json.h"
#include "core/proto/tmesh_file.h"
#include "core/read_file.h"
#include "google/protobuf/util/json_util.h"

namespace ispq::cli {

absl::Status WriteResultFile(const std::string& path, const v1::QuantizationResult& result) {
  std::ofstream out(path, std::ios::trunc);
  out << MessageToJson(result) << "\n";
  out.close();
  if (!out) return absl::InternalError(absl::StrCat(path, ": cannot write the result"));
  return absl::OkStatus();
}

absl::StatusOr<v1::QuantizationResult> ReadResultFile(const std::string& path) {
  absl::StatusOr<std::string> json = ReadFileToString(path, kMaxTMeshFileBytes);
  if (!json.ok()) return json.status();
  v1::QuantizationResult result;
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = true;
  const auto status = google::protobuf::util::JsonStringToMessage(*json, &result, options);
  if (!status.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(path, ": not a quantization result: ", std::string(status.message())));
  }
  return result;
}

void PrintResultSummary(const v1::QuantizationResult& result, std::ostream& out) {
  const v1::QuantizationStats& s = result.stats();
  out << (result.valid() ? "valid" : "NOT valid") << " quantization of " << result.mesh_name()
      << " at scaling " << result.scaling() << " (" << v1::Termination_Name(result.termination())
      << ")\n"
      << "  objective " << result.objective() << ", " << result.hexes() << " hexes, "
      << result.q_size() << " arcs\n";
  if (result.has_lower_bound()) {
    out << "  lower bound " << result.lower_bound() << ", gap " << 100 * result.gap()
        << " % (for the separation rows found)\n";
  }
  out << "  " << s.lp_solves() << " LP solves, sheets " << s.sheets_inflating() << " inflating / "
      << s.sheets_deflating() << " deflating / " << s.sheets_mixed() << " mixed, "
      << s.separation_rounds() << " separation rounds (" << s.separation_rows() << " rows)\n";
  if (s.covered_checks() > 0) {
    out << "  " << s.covered_checks()
        << " greedy checks answered by another root's sheet (large subproblems)\n";
  }
  if (s.milp_solves() > 0) {
    out << "  exact: " << s.milp_solves() << " MILP solves, " << s.milp_nodes() << " nodes, "
        << s.milp_incumbents() << " candidates checked, " << s.exact_seconds() << " s\n";
  }
  out << "  solved in " << s.solve_seconds() << " s\n";
}

int OutputResult(const v1::QuantizationResult& result, const std::string& out_path, bool json) {
  if (!out_path.empty()) {
    if (absl::Status written = WriteResultFile(out_path, result); !written.ok()) {
      std::cerr << "ispq: " << written.message() << "\n";
      return kExitFailed;
    }
  }
  if (json) {
    std::cout << MessageToJson(result) << "\n";
  } else {
    PrintResultSummary(result, std::cout);
  }
  return result.valid() ? kExitOk : kExitInvalidResult;
}

}  // namespace ispq::cli
