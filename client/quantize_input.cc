// SPDX-License-Identifier: Apache-2.0
#include "client/quantize_input.h"

#include <iostream>
#include <utility>

#include "client/exit_codes.h"
#include "client/mesh_file_input.h"
#include "core/proto/quantization_proto.h"

namespace ispq::cli {

namespace {

absl::StatusOr<MeshFile> LoadMesh(const std::string& mesh_path, MeshUse use) {
  if (use == MeshUse::kSendToServer) return LoadMeshFile(mesh_path);
  absl::StatusOr<TMesh> mesh = LoadMeshModel(mesh_path);
  if (!mesh.ok()) return mesh.status();
  return MeshFile{TMeshMessage(), *std::move(mesh)};
}

}  // namespace

QuantizeInputOrExit LoadQuantizeInput(const std::string& mesh_path,
                                      const v1::QuantizationOptions& quantization, MeshUse use) {
  QuantizeInputOrExit loaded;
  absl::StatusOr<MeshFile> file = LoadMesh(mesh_path, use);
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
