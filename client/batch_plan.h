// SPDX-License-Identifier: Apache-2.0
// What `ispq batch` will run: one job per mesh file and scaling, each with the result file it
// writes and the request id that makes its submission safe to repeat.
//
// Directories are searched recursively for T-mesh files (.tmesh.json, .tmesh.pb, .tmesh.binpb);
// a job's name is the mesh's path relative to the directory it was found in (a file given by
// itself: its file name), without the extension, plus the scaling ("hex-me/s07c_notch L25"). Its
// result file mirrors that name under the output directory
// (OUT/hex-me/s07c_notch.L25.result.json), so a batch rerun with the same output directory
// finds what it already wrote.
#ifndef ISPQ_CLIENT_BATCH_PLAN_H_
#define ISPQ_CLIENT_BATCH_PLAN_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "ispq/v1/quantization.pb.h"
#include "ispq/v1/service.pb.h"

namespace ispq::cli {

struct BatchJob {
  std::string mesh_path;
  std::string name;  // "hex-me/s07c_notch L25": in progress lines, the summary and errors
  v1::QuantizationOptions options;
  std::string result_path;
};

// The jobs for every mesh under `inputs` (files or directories) times every entry of
// `variants` (the options of each scaling), by mesh name and then in the order of `variants`.
// INVALID_ARGUMENT naming the input that is neither a T-mesh file nor a directory holding one, or
// two inputs that would write the same result file.
absl::StatusOr<std::vector<BatchJob>> PlanBatch(
    const std::vector<std::string>& inputs, const std::vector<v1::QuantizationOptions>& variants,
    const std::string& out_dir);

// "L25", "s2.5" or "h10000": how a scaling is named in job names and result files.
std::string ScalingLabel(const v1::Scaling& scaling);

// A request id (AIP-155) that is the same whenever the same request is sent for the same result
// file, and differs otherwise: a batch that resubmits after a lost answer or a restart gets its
// job back instead of a second one.
std::string BatchRequestId(const v1::QuantizeRequest& request, const std::string& result_path);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_BATCH_PLAN_H_
