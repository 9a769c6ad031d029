// SPDX-License-Identifier: Apache-2.0
// What the web view draws of a T-mesh, encoded compactly: the nodes' positions and the arcs as
// segments between them, with each arc's id (its index into q), unscaled target length, bundle (the
// arcs consistency alone forces to equal length, core/arc_bundles.h) and criticality; and the
// patches as cycles of nodes, for translucent faces. Binary, so
// that a browser reads it into typed arrays without parsing: a 100k-arc mesh is about 2.5 MB and
// is drawn straight from the buffer.
//
// Above `max_arcs` arcs the segments are decimated: every critical arc is sent (those are what
// separation protects and what shapes the part) and every k-th other arc, k the smallest stride
// that keeps the total near `max_arcs`; the header says so (sent arcs, stride), so that a 1M-arc
// part opens in seconds and the page can tell its user what it shows. A decimated mesh sends its
// critical patches only (boundary and feature surfaces: the part's shape).
//
// Layout, little-endian, every section 4-byte aligned:
//   int32[8]  header: magic 0x31475149 ("IQG1"), nodes N, arcs of the mesh A, arcs sent M,
//             stride k (1: all arcs sent), bundles B, patches sent P, cycle entries C
//   float32[3N]  node positions x, y, z
//   int32[M]     arc ids, ascending
//   int32[2M]    from, to node of each sent arc
//   float32[M]   unscaled target length l
//   int32[M]     bundle id
//   uint8[M]     flags: 1 critical, 2 singular, 4 feature, 8 boundary; padded with zeros to 4
//   int32[P]     patch ids, ascending
//   int32[P+1]   offsets into the cycle entries: patch i is entries offsets[i] .. offsets[i+1]-1
//   int32[C]     the nodes around each patch, in the order of its halfpatch 2p's cycle
//   uint8[P]     patch flags: 4 feature, 8 boundary; padded with zeros to 4
//   int32[B]     the smallest arc of each bundle, ascending (bundles are numbered by it): how a
//                view finds the bundle of an arc it was not sent, such as one a result's
//                separation row names (QuantizationResult.separation_rows)
#ifndef ISPQ_SERVER_HTTP_MESH_GEOMETRY_H_
#define ISPQ_SERVER_HTTP_MESH_GEOMETRY_H_

#include <cstdint>
#include <string>

#include "core/tmesh.h"
#include "server/model/mesh_positions.h"

namespace ispq::server::http {

inline constexpr int32_t kGeometryMagic = 0x31475149;  // "IQG1" in little-endian bytes
inline constexpr int kDefaultGeometryArcs = 100000;

enum GeometryFlag : uint8_t {
  kGeometryCritical = 1,
  kGeometrySingular = 2,
  kGeometryFeature = 4,
  kGeometryBoundary = 8,
};

// `positions` has one entry per node of `mesh`. `max_arcs` >= 1.
std::string EncodeMeshGeometry(const TMesh& mesh, const NodePositions& positions, int max_arcs);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_MESH_GEOMETRY_H_
