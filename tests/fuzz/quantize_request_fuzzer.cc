// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the bytes of an ispq.v1.QuantizeRequest, as the server receives them,
// through parsing, the loader, the options (scaling resolution, limits) and a bounded
// quantization. Seeded with requests for the real T-meshes (ispq_fuzz_seeds).
#include <cstddef>
#include <cstdint>

#include "core/proto/quantization_proto.h"
#include "core/proto/tmesh_from_proto.h"
#include "ispq/v1/service.pb.h"
#include "tests/fuzz/bounded_quantize.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ispq::v1::QuantizeRequest request;
  if (!request.ParseFromArray(data, static_cast<int>(size))) return 0;
  if (!request.has_mesh()) return 0;
  const absl::StatusOr<ispq::TMesh> mesh = ispq::TMeshFromProto(request.mesh());
  if (!mesh.ok()) return 0;
  const absl::StatusOr<ispq::QuantizeOptions> options =
      ispq::QuantizeOptionsFromProto(request.options(), *mesh);
  if (!options.ok()) return 0;
  ispq::fuzz::QuantizeBounded(*mesh, *options);
  return 0;
}
