// SPDX-License-Identifier: Apache-2.0
#include "server/http/mesh_geometry.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"

namespace ispq::server::http {
namespace {

// The browser reads the buffer as typed arrays, which are in the machine's byte order; the
// format says little-endian, so the bytes are copied as they are only where that holds.
static_assert(std::endian::native == std::endian::little, "the geometry is written little-endian");

template <typename T>
void Append(std::string& out, const T* values, size_t count) {
  out.append(reinterpret_cast<const char*>(values), count * sizeof(T));
}

// The arcs sent: all of them up to `max_arcs`, else every critical arc and every k-th other.
std::vector<ArcId> SentArcs(const TMesh& mesh, int max_arcs, int* stride) {
  std::vector<ArcId> sent;
  *stride = 1;
  if (mesh.num_arcs() <= max_arcs) {
    sent.resize(mesh.num_arcs());
    for (ArcId a = 0; a < mesh.num_arcs(); ++a) sent[a] = a;
    return sent;
  }
  int64_t critical = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) critical += mesh.arc_critical(a) ? 1 : 0;
  const int64_t others = mesh.num_arcs() - critical;
  const int64_t room = std::max<int64_t>(1, max_arcs - critical);
  *stride = static_cast<int>((others + room - 1) / room);
  int64_t other = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    if (mesh.arc_critical(a) || other++ % *stride == 0) sent.push_back(a);
  }
  return sent;
}

// The patches sent: all of them with all arcs, else the critical ones (boundary and feature
// surfaces: the part's shape), which a decimated view still shows whole.
std::vector<PatchId> SentPatches(const TMesh& mesh, bool decimated) {
  std::vector<PatchId> sent;
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    if (!decimated || mesh.patch_critical(p)) sent.push_back(p);
  }
  return sent;
}

uint8_t FlagsOf(const TMesh& mesh, ArcId a) {
  return (mesh.arc_critical(a) ? kGeometryCritical : 0) |
         (mesh.arc_singular(a) != 0 ? kGeometrySingular : 0) |
         (mesh.arc_feature(a) ? kGeometryFeature : 0) |
         (mesh.arc_boundary(a) ? kGeometryBoundary : 0);
}

}  // namespace

std::string EncodeMeshGeometry(const TMesh& mesh, const NodePositions& positions, int max_arcs) {
  int stride = 1;
  const std::vector<ArcId> sent = SentArcs(mesh, std::max(1, max_arcs), &stride);
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const size_t m = sent.size();

  std::vector<int32_t> ends(2 * m), bundle(m);
  std::vector<float> length(m);
  std::vector<uint8_t> flags((m + 3) / 4 * 4, 0);
  for (size_t i = 0; i < m; ++i) {
    const ArcId a = sent[i];
    ends[2 * i] = mesh.arc_from(a);
    ends[2 * i + 1] = mesh.arc_to(a);
    length[i] = static_cast<float>(mesh.arc_length(a));
    bundle[i] = bundles.bundle_of(a);
    flags[i] = FlagsOf(mesh, a);
  }
  // Each patch as the cycle of its nodes (the tail of each halfarc of halfpatch 2p).
  const std::vector<PatchId> patches = SentPatches(mesh, stride > 1);
  std::vector<int32_t> offsets = {0}, cycle_nodes;
  std::vector<uint8_t> patch_flags((patches.size() + 3) / 4 * 4, 0);
  for (size_t i = 0; i < patches.size(); ++i) {
    for (HalfarcId h : mesh.patch_cycle(patches[i])) cycle_nodes.push_back(mesh.tail(h));
    offsets.push_back(static_cast<int32_t>(cycle_nodes.size()));
    patch_flags[i] = (mesh.patch_boundary(patches[i]) ? kGeometryBoundary : 0) |
                     (mesh.patch_feature(patches[i]) ? kGeometryFeature : 0);
  }
  const int32_t header[8] = {kGeometryMagic,
                             mesh.num_nodes(),
                             mesh.num_arcs(),
                             static_cast<int32_t>(m),
                             stride,
                             bundles.num_bundles(),
                             static_cast<int32_t>(patches.size()),
                             static_cast<int32_t>(cycle_nodes.size())};
  std::string out;
  out.reserve(sizeof(header) + positions.size() * 12 + m * 20 + flags.size() + patches.size() * 9 +
              cycle_nodes.size() * 4 + bundles.num_bundles() * 4 + 8);
  Append(out, header, 8);
  for (const std::array<float, 3>& p : positions) Append(out, p.data(), 3);
  Append(out, sent.data(), m);
  Append(out, ends.data(), 2 * m);
  Append(out, length.data(), m);
  Append(out, bundle.data(), m);
  Append(out, flags.data(), flags.size());
  Append(out, patches.data(), patches.size());
  Append(out, offsets.data(), offsets.size());
  Append(out, cycle_nodes.data(), cycle_nodes.size());
  Append(out, patch_flags.data(), patch_flags.size());
  for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
    const int32_t first_arc = bundles.arcs(b)[0];
    Append(out, &first_arc, 1);
  }
  return out;
}

}  // namespace ispq::server::http
