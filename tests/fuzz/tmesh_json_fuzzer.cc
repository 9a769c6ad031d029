// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: a T-mesh JSON document (the format of proto/README.md, as read by
// `ispq quantize FILE`) through the parser, the loader and, if it loads, a bounded quantization
// at the level picked by the input's length. Seeded with the real T-meshes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "tests/fuzz/bounded_quantize.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view json(reinterpret_cast<const char*>(data), size);
  const absl::StatusOr<ispq::v1::TMesh> proto = ispq::ParseTMeshJson(json);
  if (!proto.ok()) return 0;
  const absl::StatusOr<ispq::TMesh> mesh = ispq::TMeshFromProto(*proto);
  if (!mesh.ok() || mesh->levels().empty()) return 0;
  ispq::QuantizeOptions options;
  options.scaling = mesh->levels()[size % mesh->levels().size()].scaling;
  ispq::fuzz::QuantizeBounded(*mesh, options);
  return 0;
}
