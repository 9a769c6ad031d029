// SPDX-License-Identifier: Apache-2.0
// Synthetic T-meshes for unit tests: a block layout in one global integer grid, turned into a
// complete ispq.v1.TMesh.
//
// Tests of the separation search and of the quantizer need tiny meshes whose answers can be
// worked out by hand (core/README.md, section Cases with known answers). BuildGridTMesh takes a
// few axis-aligned boxes and writes what the reference exporter would write for that motorcycle
// complex: nodes at block corners and T-junctions, every block face split into patches by the
// blocks on the other side, arcs split at every node, radial orders, singular marks, feature and
// critical flags, critical entities, levels and stats. Blocks can be expressed in rotated frames,
// which exercises transitions and frame handling without changing the geometry. Every mesh it
// returns passes TMeshFromProto (core/proto/tmesh_from_proto.h), the product's own format
// checker.
//
// Element ids are deterministic but not meaningful; tests name elements by grid points through
// the lookups of GridTMesh (e.g. "the arc from (1,1,0) to (1,1,1)").
#ifndef ISPQ_TESTS_SUPPORT_GRID_TMESH_BUILDER_H_
#define ISPQ_TESTS_SUPPORT_GRID_TMESH_BUILDER_H_

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq::testing {

// A point of the global integer grid, (u, v, w). Coordinates are >= 0.
using GridPoint = std::array<int, 3>;

// An axis-aligned box [lo, hi] of the grid. A block has lo < hi on every axis; a flat box
// (lo == hi on exactly one axis) describes a rectangle, e.g. a patch.
struct GridBox {
  GridPoint lo;
  GridPoint hi;
};

struct GridTMeshSpec {
  std::string name = "grid";
  // The blocks, in block id order. Their interiors must not overlap, and they must meet in a
  // manifold way (no two blocks sharing only an edge or a corner where nothing else is).
  std::vector<GridBox> blocks;
  // spacing[k][i] is the continuous length of the grid interval [i, i + 1] along axis k; an
  // arc's target length is the sum over its intervals. Empty means 1.0 for every interval.
  std::array<std::vector<double>, 3> spacing;
  // Grid points that are nodes to mark as feature nodes. Ends of feature curves (nodes with a
  // feature arc count other than 0 and 2) are marked as well, as upstream guarantees.
  std::vector<GridPoint> feature_nodes;
  // Axis-aligned segments whose arcs are feature arcs; the endpoints must be nodes and the
  // segment must be covered by arcs.
  std::vector<std::pair<GridPoint, GridPoint>> feature_arcs;
  // Flat boxes whose patches are feature patches; each must be exactly a union of patches.
  std::vector<GridBox> feature_patches;
  // (block id, Rotation index 0..23): that block's frame is the global frame rotated by
  // Rotation::FromIndex(index), i.e. a global direction d is R d in the block's frame.
  std::vector<std::pair<int, int>> block_rotations;
};

// A built mesh together with the grid geometry of its elements, so that tests can name nodes,
// arcs and patches by grid points.
class GridTMesh {
 public:
  const v1::TMesh& proto() const { return proto_; }
  v1::TMesh* mutable_proto() { return &proto_; }

  const GridPoint& node_point(int node) const { return node_points_[node]; }
  // The arc's end points, `from` first; they differ on one axis, where `from` is lower.
  const std::pair<GridPoint, GridPoint>& arc_ends(int arc) const { return arc_ends_[arc]; }
  // The patch's rectangle, a flat box.
  const GridBox& patch_rect(int patch) const { return patch_rects_[patch]; }

  // The node at p, or -1.
  int NodeAt(const GridPoint& p) const;
  // The arc joining the nodes at a and b (in either order), or -1 if there is none.
  int ArcBetween(const GridPoint& a, const GridPoint& b) const;
  // The halfarc running from the node at `from` to the node at `to`, or -1.
  int HalfarcFromTo(const GridPoint& from, const GridPoint& to) const;
  // The halfarcs of the straight chain of arcs from `from` to `to` (on one axis), in order;
  // empty if the segment is not a chain of arcs between two nodes.
  std::vector<int> HalfarcChain(const GridPoint& from, const GridPoint& to) const;
  // The patch whose rectangle is exactly `rect`, or -1.
  int PatchAt(const GridBox& rect) const;
  // q of every arc (by arc id) from an integer length per grid interval: intervals[k][i] is the
  // length of [i, i + 1] along axis k, and an arc's q is the sum over the intervals it spans, so
  // the result is consistent by construction.
  std::vector<int64_t> QFromIntervals(const std::array<std::vector<int64_t>, 3>& intervals) const;

 private:
  friend class GridTMeshBuilder;

  v1::TMesh proto_;
  std::vector<GridPoint> node_points_;
  std::vector<std::pair<GridPoint, GridPoint>> arc_ends_;
  std::vector<GridBox> patch_rects_;
  std::map<GridPoint, int> node_index_;
  std::map<std::pair<GridPoint, GridPoint>, int> arc_index_;    // (from, to) -> arc
  std::map<std::pair<GridPoint, GridPoint>, int> patch_index_;  // (lo, hi) -> patch
};

absl::StatusOr<GridTMesh> BuildGridTMesh(const GridTMeshSpec& spec);
// BuildGridTMesh of a spec the test knows to be valid: the test binary aborts with the error
// otherwise.
GridTMesh BuildGridTMeshOrDie(const GridTMeshSpec& spec);

// Eight unit blocks of one layer around the empty middle of a 3 x 3 square: a part with a handle
// (the two sides of the hole may differ in length under consistency alone).
GridTMeshSpec RingAroundAHole();

// A 2D layout (rectangles in (u, v)) extruded by one block layer along w, the way core/README.md,
// section Cases with known answers (T8), turns its 2D examples into T-meshes: every rectangle
// becomes the block [lo, hi] x [0, 1], the faces w = 0 and w = 1 are boundary. A 2D feature node
// becomes the feature arc through the layer at that point, a 2D feature arc the feature patch
// (wall) over that segment. 2D point (u, v) is grid point (u, v, 0) or (u, v, 1).
using GridPoint2 = std::array<int, 2>;

struct GridRect {
  GridPoint2 lo;
  GridPoint2 hi;
};

struct GridLayout2D {
  std::string name = "layout";
  std::vector<GridRect> blocks;
  std::array<std::vector<double>, 2> spacing;  // as GridTMeshSpec::spacing, for u and v
  double layer_height = 1.0;                   // continuous length of the w layer
  std::vector<GridPoint2> feature_nodes;
  std::vector<std::pair<GridPoint2, GridPoint2>> feature_arcs;
};

GridTMeshSpec ExtrudeLayout(const GridLayout2D& layout);

// The mesh as compact JSON through protobuf's JSON mapping (the `*.tmesh.json` format, all
// fields written), e.g. to feed `ispq stats` or to write a fixture.
absl::StatusOr<std::string> TMeshToJson(const v1::TMesh& mesh);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_GRID_TMESH_BUILDER_H_
