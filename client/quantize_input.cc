// SPDX-License-Identifier: Apache-2.0
#include "client/quantize_input.h"

#include <iostream>
#include <utility>

#include "client/exit_codes.h"
#include "client/mesh_file_input.h"
#include "core/proto/quantization_proto.h"

namespace ispq::cli {

QuantizeInputOrExit LoadQuantizeInput(const std::string& mesh_path,
                                      const v1::QuantizationOptions& quantization) {
  QuantizeInputOrExit loaded;
  absl::StatusOr<MeshFile> file = LoadMeshFile(mesh_path);
  if (!file.ok()) {
    std::cerr << "ispq: " << file.status().message() << "\n";
    loaded.exit_code = kExitInvalidInput;
    return loaded;
  }
  absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(quantization, file->mesh);
  if (!options.ok()) {
    std::cerr << "ispq: " << options.status().message() << "\n";
    loaded.exit_code = kExitUsage;
    return loaded;
  }
  loaded.input = QuantizeInput{std::move(file->proto), std::move(file->mesh), *options};
  return loaded;
}

v1::QuantizeRequest& MakeQuantizeRequest(QuantizeInput& input,
                                         const v1::QuantizationOptions& quantization) {
  auto* request = input.proto.CreateOnArena<v1::QuantizeRequest>();
  request->mutable_mesh()->Swap(input.proto.mutable_message());
  *request->mutable_options() = quantization;
  return *request;
}

}  // namespace ispq::cli
