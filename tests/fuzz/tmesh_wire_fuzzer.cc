// SPDX-License-Identifier: Apache-2.0
// libFuzzer target, differential: any bytes through the element-at-a-time decoder of uploads
// (core/proto/tmesh_from_wire.h), read in pieces whose size the input's first byte picks (chunk
// borders anywhere), against protobuf's parser followed by the message decoder
// (core/proto/tmesh_from_proto.h). Bytes the parser refuses must be refused; bytes it accepts
// must get the same answer: the same error, or a mesh with the same counts. Seeded with the real
// T-meshes in binary form (ispq_fuzz_seeds).
#include <cstddef>
#include <cstdint>
#include <memory>

#include "core/mesh_stats.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/proto/tmesh_from_wire.h"
#include "google/protobuf/io/zero_copy_stream_impl_lite.h"
#include "ispq/v1/tmesh.pb.h"

namespace {

bool SameCounts(const ispq::TMesh& a, const ispq::TMesh& b) {
  const ispq::MeshStats x = ispq::ComputeMeshStats(a), y = ispq::ComputeMeshStats(b);
  return x.nodes == y.nodes && x.arcs == y.arcs && x.patches == y.patches && x.blocks == y.blocks &&
         x.critical_entities == y.critical_entities && x.bundles == y.bundles &&
         a.levels().size() == b.levels().size();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const int piece = 1 + (size > 0 ? data[0] : 0) * 7;
  const absl::StatusOr<ispq::TMesh> streamed = ispq::TMeshFromWire([&] {
    return std::make_unique<google::protobuf::io::ArrayInputStream>(data, static_cast<int>(size),
                                                                    piece);
  });
  ispq::v1::TMesh parsed;
  if (!parsed.ParseFromArray(data, static_cast<int>(size))) {
    if (streamed.ok()) __builtin_trap();  // bytes that are no message decoded to a mesh
    return 0;
  }
  const absl::StatusOr<ispq::TMesh> whole = ispq::TMeshFromProto(parsed);
  if (whole.status() != streamed.status()) __builtin_trap();
  if (whole.ok() && !SameCounts(*whole, *streamed)) __builtin_trap();
  return 0;
}
