// Synthetic T-meshes for unit tests: a block layout in one global integer grid, turned into a
// complete ispq.v1.TMesh.
//
// Tests of the separation search and of the quantizer need tiny meshes whose answers can be
// worked out by hand (shared/separation.md section 7). BuildGridTMesh takes a few axis-aligned
// boxes and writes what the reference exporter would write for that motorcycle complex: nodes
// at block corners and T-junctions, every block face split into patches by the blocks on the
// other side, arcs split at every node, radial orders, singular marks, feature and critical
// flags, critical entities, levels and stats. Blocks can be expressed in rotated frames, which
// exercises transitions and frame handling without changing the geometry. Every mesh it returns
// passes TMeshFromProto (core/proto/tmesh_from_proto.h) and shared/tools/check_tmesh.py.
//
// Element ids are deterministic but not meaningful; tests name elements by grid points through
// the lookups of GridTMesh (e.g. "the arc from (1,1,0) to (1,1,1)").
#ifndef ISPQ_TESTS_SUPPORT_GRID_TMESH_BUILDER_H_
#define ISPQ_TESTS_SUPPORT_GRID_TMESH_BUILDER_H_

#include <array>
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

// A 2D layout (rectangles in (u, v)) extruded by one block layer along w, the way
// shared/separation.md section 7 (T8) turns its 2D examples into T-meshes: every rectangle
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

// The 2D worked examples of shared/separation.md section 5, as layouts with the target lengths
// given there. Points are grid indices, not target coordinates.
//
// Example A: u indices 0..3 at target u 0, 2.5, 2.5 + g1, 3.5 + g1; v indices 0..3 at 0, 0.5,
// 1, 2. F = (1, 2) is the feature node, I = (1, 1), K = (2, 1), J = (2, 0), x0 = (0, 0).
// `g1_length` is the length of arc I-K: 0.5 in section 5.1, 3 in test T11.
GridLayout2D SeparationExampleA(double g1_length = 0.5);
// Example B: u indices at target u 0, 3, t_u, 5, 6 in increasing order, merged where equal; v
// indices 0..4 at -1..3. With f, t, k the u indices of 3, t_u and 5: F = (f, 3), I = (f, 2),
// K = (k, 2), Q = (k, 1), T = (t, 1). t_u is the target u of T (0 < t_u < 5): 3.2 in section
// 5.2, 3, 2.5 and 3.5 in test T12. Its feature_nodes are {F, T}.
GridLayout2D SeparationExampleB(double t_u = 3.2);
// Example C, no features: u and v indices equal the target coordinates. M = (0, 0), N = (1, 0),
// O = (3, 0), H = (1, 1), K = (3, 1), E = (1, 2), F = (2, 2), C = (2, 3), I = (3, 3); the slot
// [1, 3] x [1, 2] and the gap [2, 3] x [2, 3] are empty.
GridLayout2D SeparationExampleC();

// A T-mesh on which the sheet LP of the ISP paper (eq. 2) has only half-integral optima: the
// "U-turn of T-junctions" of the paper's Figs. 6 and 7. Seven blocks, u in [0, 2], wind around
// an empty tunnel [0, 2] x [1, 2] x [1, 2] along u; half of them span only u in [0, 1] or
// [1, 2], so a sheet through the u-half [0, 1] comes back round the tunnel in the other half.
// Forcing the root arc (u-length 2) to 1, `min sum_a q_a` subject to patch consistency,
// q >= 0, q_root >= 1 has the optimum 11.5 (checked with CLP; also fractional for 198 of 200
// random positive weight vectors): q_root = 1 and 1/2 on the 21 `half_arcs`. No integral
// solution reaches 11.5; doubling gives an integer sheet (lcd 2).
//
// Fig. 6 itself is a 2D layout whose U-turn needs a rotational transition (a cone
// singularity), which one global grid cannot express: every planar axis-aligned layout, and its
// extrusion, has a totally unimodular consistency matrix per axis and integral LP vertices.
struct HalfIntegerSheetExample {
  GridTMeshSpec spec;
  std::pair<GridPoint, GridPoint> root;
  std::vector<std::pair<GridPoint, GridPoint>> half_arcs;
};
HalfIntegerSheetExample MakeHalfIntegerSheetExample();

// The mesh as compact JSON through protobuf's JSON mapping (the `*.tmesh.json` format, all
// fields written), e.g. to feed shared/tools/check_tmesh.py or to write a fixture.
absl::StatusOr<std::string> TMeshToJson(const v1::TMesh& mesh);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_GRID_TMESH_BUILDER_H_
