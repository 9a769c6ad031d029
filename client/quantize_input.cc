#include "client/quantize_input.h"

#include <iostream>
#include <utility>

#include "client/exit_codes.h"
#include "core/proto/quantization_proto.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"

namespace ispq::cli {

QuantizeInputOrExit LoadQuantizeInput(const std::string& mesh_path,
                                      const v1::QuantizationOptions& quantization) {
  QuantizeInputOrExit loaded;
  absl::StatusOr<v1::TMesh> proto = ReadTMeshFile(mesh_path);
  if (!proto.ok()) {
    std::cerr << "ispq: " << proto.status().message() << "\n";
    loaded.exit_code = kExitInvalidInput;
    return loaded;
  }
  absl::StatusOr<TMesh> mesh = TMeshFromProto(*proto);
  if (!mesh.ok()) {
    std::cerr << "ispq: " << mesh_path << ": " << mesh.status().message() << "\n";
    loaded.exit_code = kExitInvalidInput;
    return loaded;
  }
  absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(quantization, *mesh);
  if (!options.ok()) {
    std::cerr << "ispq: " << options.status().message() << "\n";
    loaded.exit_code = kExitUsage;
    return loaded;
  }
  loaded.input = QuantizeInput{*std::move(proto), *std::move(mesh), *options};
  return loaded;
}

}  // namespace ispq::cli
