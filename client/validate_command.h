// SPDX-License-Identifier: Apache-2.0
// `ispq validate FILE --result RESULT.json`: checks any quantization, also one produced
// elsewhere, with the product's validator (consistency, block extents, simple rows, separation
// search) and prints the verdict with the offending elements.
#ifndef ISPQ_CLIENT_VALIDATE_COMMAND_H_
#define ISPQ_CLIENT_VALIDATE_COMMAND_H_

#include <string>

#include "ispq/v1/quantization.pb.h"

namespace ispq::cli {

struct ValidateCommandOptions {
  std::string mesh_path;
  std::string result_path;
  v1::Scaling scaling;  // for the objective; validity does not depend on it
  bool reference_block_boxes = false;
  bool json = false;
};

int RunValidate(const ValidateCommandOptions& options);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_VALIDATE_COMMAND_H_
