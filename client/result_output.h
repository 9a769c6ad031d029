// SPDX-License-Identifier: Apache-2.0
// Writing quantization results: the result file (the JSON form of ispq.v1.QuantizationResult)
// and the one-paragraph summary a person reads.
#ifndef ISPQ_CLIENT_RESULT_OUTPUT_H_
#define ISPQ_CLIENT_RESULT_OUTPUT_H_

#include <ostream>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "ispq/v1/quantization.pb.h"

namespace ispq::cli {

absl::Status WriteResultFile(const std::string& path, const v1::QuantizationResult& result);
// Reads a result file; unknown keys are ignored so results produced elsewhere can be checked.
absl::StatusOr<v1::QuantizationResult> ReadResultFile(const std::string& path);

void PrintResultSummary(const v1::QuantizationResult& result, std::ostream& out);

// What `ispq quantize` (local or remote) and `ispq watch` do with a result: write the result
// file if `out_path` is set, print the result JSON (`json`) or the summary on stdout, and return
// the exit code: 0 for a valid result, 4 for an invalid one, 5 if the file cannot be written.
int OutputResult(const v1::QuantizationResult& result, const std::string& out_path, bool json);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_RESULT_OUTPUT_H_
