// SPDX-License-Identifier: Apache-2.0
#include "tests/support/grid_tmesh_builder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <initializer_list>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/direction.h"
#include "core/resolution_levels.h"
#include "core/rotation.h"
#include "google/protobuf/util/json_util.h"

namespace ispq::testing {
namespace {

using Vec3 = std::array<double, 3>;

// Ids follow the order w, then v, then u of an element's lowest point, so that the bottom layer
// of a layered mesh comes first and ids read like rows of a picture.
GridPoint SortKey(const GridPoint& p) { return {p[2], p[1], p[0]}; }
bool PointLess(const GridPoint& a, const GridPoint& b) { return SortKey(a) < SortKey(b); }

std::string PointString(const GridPoint& p) {
  return absl::StrCat("(", p[0], ",", p[1], ",", p[2], ")");
}

// The two axes spanning the plane normal to axis k, in right-handed order: e_i x e_j = e_k.
int FirstInPlaneAxis(int k) { return (k + 1) % 3; }
int SecondInPlaneAxis(int k) { return (k + 2) % 3; }

// The single axis on which a and b differ, or -1.
int SegmentAxis(const GridPoint& a, const GridPoint& b) {
  int axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (a[k] == b[k]) continue;
    if (axis >= 0) return -1;
    axis = k;
  }
  return axis;
}

v1::UVWDir DirToProto(Dir d) { return static_cast<v1::UVWDir>(1 << DirIndex(d)); }

// Upstream bits of a block edge or corner: the OR of its face sides, one per axis in `axes`,
// positive where bit `axis` of `code` is set (code as in core/direction.h's corner code).
int SidesBits(int code, std::initializer_list<int> axes) {
  int bits = 0;
  for (int axis : axes) bits |= 1 << DirIndex(MakeDir(axis, (code & (1 << axis)) == 0));
  return bits;
}

// Number of connected groups among the octants in `mask` (bit o = octant o), where octants are
// adjacent when they share a face (differ in one bit).
int OctantComponents(int mask) {
  int seen = 0, components = 0;
  for (int start = 0; start < 8; ++start) {
    if (!(mask & (1 << start)) || (seen & (1 << start))) continue;
    ++components;
    std::vector<int> stack = {start};
    seen |= 1 << start;
    while (!stack.empty()) {
      const int o = stack.back();
      stack.pop_back();
      for (int axis = 0; axis < 3; ++axis) {
        const int next = o ^ (1 << axis);
        if ((mask & (1 << next)) && !(seen & (1 << next))) {
          seen |= 1 << next;
          stack.push_back(next);
        }
      }
    }
  }
  return components;
}

// A patch as geometry: a rectangle in a plane normal to `axis`, with the blocks on its sides.
struct PatchGeom {
  GridBox rect;  // rect.lo[axis] == rect.hi[axis]
  int axis = 0;
  std::array<int, 2> blocks = {-1, -1};
  // blocks[k] lies on the positive side of the plane, i.e. the patch is on its NEG face.
  std::array<bool, 2> block_above = {false, false};

  // The global face side of blocks[k] the patch lies on.
  Dir FaceSide(int k) const { return MakeDir(axis, block_above[k]); }
};

}  // namespace

// Builds the mesh in dependency order: geometry (patches, nodes, arcs) first, then the ids and
// incidences of the proto, then the flags derived from them, then critical entities.
class GridTMeshBuilder {
 public:
  explicit GridTMeshBuilder(const GridTMeshSpec& spec) : spec_(spec), proto_(out_.proto_) {}

  absl::StatusOr<GridTMesh> Build() {
    for (absl::Status (GridTMeshBuilder::*step)() :
         {&GridTMeshBuilder::CheckSpec, &GridTMeshBuilder::CollectPatches,
          &GridTMeshBuilder::CollectNodesAndArcs, &GridTMeshBuilder::CheckManifold,
          &GridTMeshBuilder::WriteNodesAndArcs, &GridTMeshBuilder::WritePatches,
          &GridTMeshBuilder::MarkFeatures, &GridTMeshBuilder::WriteNodeTypes,
          &GridTMeshBuilder::WriteBlocks, &GridTMeshBuilder::WriteCriticalEntities,
          &GridTMeshBuilder::WriteLevelsAndStats}) {
      if (absl::Status status = (this->*step)(); !status.ok()) return status;
    }
    return std::move(out_);
  }

 private:
  template <typename... Args>
  static absl::Status Invalid(const Args&... args) {
    return absl::InvalidArgumentError(absl::StrCat(args...));
  }

  int num_blocks() const { return static_cast<int>(spec_.blocks.size()); }
  const GridBox& block(int b) const { return spec_.blocks[b]; }

  // Continuous global coordinates of a grid point.
  Vec3 Position(const GridPoint& p) const {
    return {coord_[0][p[0]], coord_[1][p[1]], coord_[2][p[2]]};
  }

  // Coordinates of p in block b's frame: the global offset from the block's lowest corner,
  // rotated. Block origins differ, so interior transitions get non-zero translations.
  Vec3 BlockUvw(int b, const GridPoint& p) const {
    const Vec3 x = Position(p), origin = Position(block(b).lo);
    return rotation_[b].Apply(Vec3{x[0] - origin[0], x[1] - origin[1], x[2] - origin[2]});
  }

  // The block owning grid cell c (the unit cube [c, c + 1]), or -1 outside every block.
  int BlockOfCell(const GridPoint& c) const {
    for (int k = 0; k < 3; ++k) {
      if (c[k] < 0 || c[k] >= cells_[k]) return -1;
    }
    return cell_block_[(static_cast<size_t>(c[2]) * cells_[1] + c[1]) * cells_[0] + c[0]];
  }

  // The block whose open box contains the doubled point q (2 * grid point + offsets), or -1.
  // Such a block owns the cell containing q, or, where q lies on grid planes, the cell just
  // below it on those axes.
  int BlockAtDoubled(const GridPoint& q) const {
    GridPoint cell;
    for (int k = 0; k < 3; ++k) cell[k] = q[k] % 2 != 0 ? (q[k] - 1) / 2 : q[k] / 2 - 1;
    const int b = BlockOfCell(cell);
    if (b < 0) return -1;
    for (int k = 0; k < 3; ++k) {
      if (!(2 * block(b).lo[k] < q[k] && q[k] < 2 * block(b).hi[k])) return -1;
    }
    return b;
  }

  // Fills the cell index; blocks that claim the same cell overlap.
  absl::Status IndexCells(const std::array<int, 3>& extent) {
    cells_ = extent;
    const double count = 1.0 * extent[0] * extent[1] * extent[2];
    if (count > 2e8) return Invalid("the grid has ", count, " cells, more than 2e8");
    cell_block_.assign(static_cast<size_t>(count), -1);
    for (int b = 0; b < num_blocks(); ++b) {
      for (int z = block(b).lo[2]; z < block(b).hi[2]; ++z) {
        for (int y = block(b).lo[1]; y < block(b).hi[1]; ++y) {
          for (int x = block(b).lo[0]; x < block(b).hi[0]; ++x) {
            int& owner = cell_block_[(static_cast<size_t>(z) * cells_[1] + y) * cells_[0] + x];
            if (owner >= 0) return Invalid("blocks ", owner, " and ", b, " overlap");
            owner = b;
          }
        }
      }
    }
    return absl::OkStatus();
  }

  absl::Status CheckSpec() {
    if (spec_.blocks.empty()) return Invalid("the spec has no blocks");
    std::array<int, 3> extent = {0, 0, 0};
    for (int b = 0; b < num_blocks(); ++b) {
      for (int k = 0; k < 3; ++k) {
        if (block(b).lo[k] < 0 || block(b).lo[k] >= block(b).hi[k]) {
          return Invalid("block ", b, ": box ", PointString(block(b).lo), "-",
                         PointString(block(b).hi), " needs 0 <= lo < hi on every axis");
        }
        extent[k] = std::max(extent[k], block(b).hi[k]);
      }
    }
    if (absl::Status indexed = IndexCells(extent); !indexed.ok()) return indexed;
    for (int k = 0; k < 3; ++k) {
      const std::vector<double>& spacing = spec_.spacing[k];
      if (!spacing.empty() && static_cast<int>(spacing.size()) < extent[k]) {
        return Invalid("spacing of axis ", k, " has ", spacing.size(), " entries, the grid needs ",
                       extent[k]);
      }
      coord_[k].assign(extent[k] + 1, 0.0);
      for (int i = 0; i < extent[k]; ++i) {
        const double length = spacing.empty() ? 1.0 : spacing[i];
        if (!std::isfinite(length) || length <= 0) {
          return Invalid("spacing of axis ", k, " interval ", i, " is not positive");
        }
        coord_[k][i + 1] = coord_[k][i] + length;
      }
    }
    rotation_.assign(num_blocks(), Rotation());
    std::vector<bool> rotated(num_blocks(), false);
    for (const auto& [b, index] : spec_.block_rotations) {
      if (b < 0 || b >= num_blocks()) return Invalid("rotation of block ", b, ": no such block");
      if (index < 0 || index >= Rotation::kCount) {
        return Invalid("rotation of block ", b, ": index ", index, " is not in 0..23");
      }
      if (rotated[b]) return Invalid("block ", b, " is rotated twice");
      rotated[b] = true;
      rotation_[b] = Rotation::FromIndex(index);
    }
    return absl::OkStatus();
  }

  // Splits every block face into the intersections with the blocks on the other side (interior
  // patches, made once from the lower block id) and rectangles covering the rest (boundary).
  absl::Status CollectPatches() {
    for (int b = 0; b < num_blocks(); ++b) {
      for (int k = 0; k < 3; ++k) {
        for (bool positive : {true, false}) {
          const int plane = positive ? block(b).hi[k] : block(b).lo[k];
          GridBox face = block(b);
          face.lo[k] = face.hi[k] = plane;
          std::vector<GridBox> covered;
          for (int n : BlocksAcross(b, k, positive)) {
            GridBox common = face;
            for (int q : {FirstInPlaneAxis(k), SecondInPlaneAxis(k)}) {
              common.lo[q] = std::max(face.lo[q], block(n).lo[q]);
              common.hi[q] = std::min(face.hi[q], block(n).hi[q]);
            }
            covered.push_back(common);
            if (b < n) patches_.push_back({common, k, {b, n}, {!positive, positive}});
          }
          for (const GridBox& rect : UncoveredRectangles(face, k, covered)) {
            patches_.push_back({rect, k, {b, -1}, {!positive, false}});
          }
        }
      }
    }
    std::sort(patches_.begin(), patches_.end(), [](const PatchGeom& x, const PatchGeom& y) {
      return std::pair(SortKey(x.rect.lo), x.axis) < std::pair(SortKey(y.rect.lo), y.axis);
    });
    return absl::OkStatus();
  }

  // The blocks across the face of block b normal to axis k (positive or negative side), ascending:
  // the owners of the cells just outside the face.
  std::vector<int> BlocksAcross(int b, int k, bool positive) const {
    const int qi = FirstInPlaneAxis(k), qj = SecondInPlaneAxis(k);
    GridPoint cell;
    cell[k] = positive ? block(b).hi[k] : block(b).lo[k] - 1;
    std::vector<int> across;
    for (cell[qi] = block(b).lo[qi]; cell[qi] < block(b).hi[qi]; ++cell[qi]) {
      for (cell[qj] = block(b).lo[qj]; cell[qj] < block(b).hi[qj]; ++cell[qj]) {
        const int n = BlockOfCell(cell);
        if (n >= 0) across.push_back(n);
      }
    }
    std::sort(across.begin(), across.end());
    across.erase(std::unique(across.begin(), across.end()), across.end());
    return across;
  }

  // Face minus the covered rectangles, as few rectangles as a greedy sweep over the overlay
  // cells finds: grow along the first in-plane axis, then along the second.
  static std::vector<GridBox> UncoveredRectangles(const GridBox& face, int k,
                                                  const std::vector<GridBox>& covered) {
    const int qi = FirstInPlaneAxis(k), qj = SecondInPlaneAxis(k);
    std::vector<int> cuts_i = {face.lo[qi], face.hi[qi]}, cuts_j = {face.lo[qj], face.hi[qj]};
    for (const GridBox& c : covered) {
      cuts_i.insert(cuts_i.end(), {c.lo[qi], c.hi[qi]});
      cuts_j.insert(cuts_j.end(), {c.lo[qj], c.hi[qj]});
    }
    for (std::vector<int>* cuts : {&cuts_i, &cuts_j}) {
      std::sort(cuts->begin(), cuts->end());
      cuts->erase(std::unique(cuts->begin(), cuts->end()), cuts->end());
    }
    const int ni = static_cast<int>(cuts_i.size()) - 1, nj = static_cast<int>(cuts_j.size()) - 1;
    std::vector<std::vector<bool>> taken(nj, std::vector<bool>(ni, false));
    for (int cj = 0; cj < nj; ++cj) {
      for (int ci = 0; ci < ni; ++ci) {
        for (const GridBox& c : covered) {
          if (c.lo[qi] <= cuts_i[ci] && cuts_i[ci + 1] <= c.hi[qi] && c.lo[qj] <= cuts_j[cj] &&
              cuts_j[cj + 1] <= c.hi[qj]) {
            taken[cj][ci] = true;
          }
        }
      }
    }
    std::vector<GridBox> pieces;
    for (int cj = 0; cj < nj; ++cj) {
      for (int ci = 0; ci < ni; ++ci) {
        if (taken[cj][ci]) continue;
        int ei = ci, ej = cj;
        while (ei + 1 < ni && !taken[cj][ei + 1]) ++ei;
        auto row_free = [&](int row) {
          for (int c = ci; c <= ei; ++c) {
            if (taken[row][c]) return false;
          }
          return true;
        };
        while (ej + 1 < nj && row_free(ej + 1)) ++ej;
        for (int row = cj; row <= ej; ++row) {
          for (int c = ci; c <= ei; ++c) taken[row][c] = true;
        }
        GridBox piece = face;
        piece.lo[qi] = cuts_i[ci];
        piece.hi[qi] = cuts_i[ei + 1];
        piece.lo[qj] = cuts_j[cj];
        piece.hi[qj] = cuts_j[ej + 1];
        pieces.push_back(piece);
      }
    }
    return pieces;
  }

  // The four corners of a patch, counterclockwise around the normal that points into
  // blocks[0]: that is the orientation of halfpatch 2p's cycle (proto/README.md, section Patches).
  std::array<GridPoint, 4> CycleCorners(const PatchGeom& patch) const {
    const int qi = FirstInPlaneAxis(patch.axis), qj = SecondInPlaneAxis(patch.axis);
    GridPoint c1 = patch.rect.lo, c3 = patch.rect.lo;
    c1[qi] = patch.rect.hi[qi];
    c3[qj] = patch.rect.hi[qj];
    // Counterclockwise around +e_axis, since e_qi x e_qj = e_axis.
    if (patch.block_above[0]) return {patch.rect.lo, c1, patch.rect.hi, c3};
    return {patch.rect.lo, c3, patch.rect.hi, c1};
  }

  // The nodes on the segment from a to b (one axis), ordered from a to b, both included.
  std::vector<GridPoint> NodesOnSegment(const GridPoint& a, const GridPoint& b) const {
    const int axis = SegmentAxis(a, b);
    const std::vector<int>& line = lines_.at(LineKey(axis, a));
    const int lo = std::min(a[axis], b[axis]), hi = std::max(a[axis], b[axis]);
    std::vector<GridPoint> nodes;
    for (auto it = std::lower_bound(line.begin(), line.end(), lo); it != line.end() && *it <= hi;
         ++it) {
      GridPoint p = a;
      p[axis] = *it;
      nodes.push_back(p);
    }
    if (a[axis] > b[axis]) std::reverse(nodes.begin(), nodes.end());
    return nodes;
  }

  static std::array<int, 3> LineKey(int axis, const GridPoint& p) {
    return {axis, p[FirstInPlaneAxis(axis)], p[SecondInPlaneAxis(axis)]};
  }

  // Nodes are the patch corners (block corners and T-junctions); arcs are the patch sides split
  // at every node on them.
  absl::Status CollectNodesAndArcs() {
    std::set<GridPoint, decltype(&PointLess)> points(&PointLess);
    for (const PatchGeom& patch : patches_) {
      for (const GridPoint& corner : CycleCorners(patch)) points.insert(corner);
    }
    for (const GridPoint& p : points) {
      out_.node_index_[p] = static_cast<int>(out_.node_points_.size());
      out_.node_points_.push_back(p);
      for (int axis = 0; axis < 3; ++axis) lines_[LineKey(axis, p)].push_back(p[axis]);
    }
    for (auto& [key, line] : lines_) std::sort(line.begin(), line.end());

    std::map<std::pair<GridPoint, int>, GridPoint> segments;  // (SortKey(from), axis) -> to
    for (const PatchGeom& patch : patches_) {
      const std::array<GridPoint, 4> corners = CycleCorners(patch);
      for (int s = 0; s < 4; ++s) {
        const std::vector<GridPoint> nodes = NodesOnSegment(corners[s], corners[(s + 1) % 4]);
        for (size_t i = 0; i + 1 < nodes.size(); ++i) {
          const auto [from, to] = std::minmax(nodes[i], nodes[i + 1], PointLess);
          segments[{SortKey(from), SegmentAxis(from, to)}] = to;
        }
      }
    }
    for (const auto& [key, to] : segments) {
      const GridPoint from = {key.first[2], key.first[1], key.first[0]};
      out_.arc_index_[{from, to}] = static_cast<int>(out_.arc_ends_.size());
      out_.arc_ends_.push_back({from, to});
      arc_axis_.push_back(key.second);
    }
    return absl::OkStatus();
  }

  // Rejects layouts that no block decomposition of a volume produces: blocks meeting only along
  // an edge or at a corner. Records the quarter turns of material around every arc on the way.
  absl::Status CheckManifold() {
    const int num_arcs = static_cast<int>(out_.arc_ends_.size());
    arc_quarter_turns_.resize(num_arcs);
    for (int a = 0; a < num_arcs; ++a) {
      const auto& [from, to] = out_.arc_ends_[a];
      const int m = arc_axis_[a], qi = FirstInPlaneAxis(m), qj = SecondInPlaneAxis(m);
      GridPoint mid = {2 * from[0], 2 * from[1], 2 * from[2]};
      mid[m] = from[m] + to[m];
      // Quadrants in counterclockwise order around +e_m.
      std::array<bool, 4> occupied;
      const int offsets[4][2] = {{1, 1}, {-1, 1}, {-1, -1}, {1, -1}};
      for (int q = 0; q < 4; ++q) {
        GridPoint x = mid;
        x[qi] += offsets[q][0];
        x[qj] += offsets[q][1];
        occupied[q] = BlockAtDoubled(x) >= 0;
      }
      const int count = static_cast<int>(std::count(occupied.begin(), occupied.end(), true));
      if (count == 2 && occupied[0] == occupied[2]) {
        return Invalid("blocks meet only along the edge ", PointString(from), "-", PointString(to));
      }
      arc_quarter_turns_[a] = count;
    }
    node_boundary_.resize(out_.node_points_.size());
    for (size_t n = 0; n < out_.node_points_.size(); ++n) {
      const GridPoint& p = out_.node_points_[n];
      int mask = 0;
      for (int o = 0; o < 8; ++o) {
        GridPoint x;
        for (int k = 0; k < 3; ++k) x[k] = 2 * p[k] + ((o & (1 << k)) ? 1 : -1);
        if (BlockAtDoubled(x) >= 0) mask |= 1 << o;
      }
      if (OctantComponents(mask) != 1 || OctantComponents(~mask & 0xff) > 1) {
        return Invalid("the blocks are not a manifold volume at ", PointString(p));
      }
      node_boundary_[n] = mask != 0xff;
    }
    return absl::OkStatus();
  }

  // Halfarc from the node at x to the adjacent node at y.
  int Halfarc(const GridPoint& x, const GridPoint& y) const { return out_.HalfarcFromTo(x, y); }

  absl::Status WriteNodesAndArcs() {
    const int num_nodes = static_cast<int>(out_.node_points_.size());
    const int num_arcs = static_cast<int>(out_.arc_ends_.size());
    std::vector<std::vector<int>> outgoing(num_nodes);
    for (int a = 0; a < num_arcs; ++a) {
      outgoing[out_.NodeAt(out_.arc_ends_[a].first)].push_back(2 * a);
      outgoing[out_.NodeAt(out_.arc_ends_[a].second)].push_back(2 * a + 1);
    }
    for (int n = 0; n < num_nodes; ++n) {
      v1::Node* node = proto_.add_nodes();
      for (double x : Position(out_.node_points_[n])) node->add_position(x);
      node->set_mesh_vertex(n);
      node->set_boundary(node_boundary_[n]);
      for (int h : outgoing[n]) node->add_outgoing_halfarcs(h);
    }
    for (int a = 0; a < num_arcs; ++a) {
      const auto& [from, to] = out_.arc_ends_[a];
      v1::Arc* arc = proto_.add_arcs();
      arc->set_from(out_.NodeAt(from));
      arc->set_to(out_.NodeAt(to));
      arc->set_length(coord_[arc_axis_[a]][to[arc_axis_[a]]] -
                      coord_[arc_axis_[a]][from[arc_axis_[a]]]);
      // proto/README.md, section Arcs: quarter turns of material around the arc minus 4 inside
      // (always 0 in a grid of boxes) or minus 2 on the boundary (-1 convex edge, +1 concave edge).
      const bool boundary = arc_quarter_turns_[a] < 4;
      arc->set_boundary(boundary);
      arc->set_singular(boundary ? arc_quarter_turns_[a] - 2 : 0);
      arc->set_critical(arc->singular() != 0);
    }
    return absl::OkStatus();
  }

  absl::Status WritePatches() {
    const int num_patches = static_cast<int>(patches_.size());
    std::vector<std::vector<int>> arc_halfpatches(out_.arc_ends_.size());
    for (int p = 0; p < num_patches; ++p) {
      const PatchGeom& geom = patches_[p];
      out_.patch_index_[{geom.rect.lo, geom.rect.hi}] = p;
      out_.patch_rects_.push_back(geom.rect);
      v1::Patch* patch = proto_.add_patches();
      for (int k = 0; k < 2; ++k) {
        patch->add_blocks(geom.blocks[k]);
        patch->add_sides(geom.blocks[k] < 0
                             ? v1::NONE
                             : DirToProto(rotation_[geom.blocks[k]].Apply(geom.FaceSide(k))));
      }
      v1::Transition* transition = patch->mutable_transition();
      Rotation rotation;
      Vec3 translation = {0, 0, 0};
      if (geom.blocks[1] >= 0) {
        // uvw_b1 = R1 (x - o1) = R1 R0^-1 uvw_b0 + R1 (o0 - o1) for block origins o0, o1.
        const int b0 = geom.blocks[0], b1 = geom.blocks[1];
        rotation = rotation_[b1].After(rotation_[b0].Inverse());
        const Vec3 o0 = Position(block(b0).lo), o1 = Position(block(b1).lo);
        translation = rotation_[b1].Apply(Vec3{o0[0] - o1[0], o0[1] - o1[1], o0[2] - o1[2]});
      }
      for (int r : rotation.SignedPermutation()) transition->add_rotation(r);
      for (double t : translation) transition->add_translation(t);
      patch->set_boundary(geom.blocks[1] < 0);
      patch->set_critical(patch->boundary());
      patch->set_ref_block(geom.blocks[0]);

      // The cycle of halfpatch 2p, side by side, each side split at its nodes.
      const std::array<GridPoint, 4> corners = CycleCorners(geom);
      std::array<std::vector<int>, kNumDirs> by_dir;
      for (int s = 0; s < 4; ++s) {
        const GridPoint &a = corners[s], &b = corners[(s + 1) % 4];
        const int axis = SegmentAxis(a, b);
        const Dir dir = rotation_[geom.blocks[0]].Apply(MakeDir(axis, b[axis] < a[axis]));
        const std::vector<GridPoint> nodes = NodesOnSegment(a, b);
        for (size_t i = 0; i + 1 < nodes.size(); ++i) {
          const int h = Halfarc(nodes[i], nodes[i + 1]);
          patch->add_halfarcs(h);
          by_dir[DirIndex(dir)].push_back(h);
          // Halfarc 2a is in the cycle of 2p if h is even, else in the reversed cycle of 2p+1.
          arc_halfpatches[h >> 1].push_back(2 * p + (h & 1));
        }
      }
      for (Dir d : kAllDirs) {  // upstream enum order
        if (by_dir[DirIndex(d)].empty()) continue;
        v1::DirectedHalfarcs* side = patch->add_halfarcs_by_dir();
        side->set_dir(DirToProto(d));
        for (int h : by_dir[DirIndex(d)]) side->add_halfarcs(h);
      }
    }
    for (size_t a = 0; a < arc_halfpatches.size(); ++a) {
      OrderRadially(static_cast<int>(a), arc_halfpatches[a]);
      for (int hp : arc_halfpatches[a]) proto_.mutable_arcs(a)->add_halfpatches(hp);
    }
    return absl::OkStatus();
  }

  // Sorts the halfpatches containing halfarc 2a counterclockwise around it (right-hand rule
  // about its direction). Then each halfpatch's block is the block the next one leaves, as in
  // the reference (blocks[hp_i] == blocks[hp_{i+1} ^ 1]). A boundary arc starts right after
  // the outside, an interior arc at its lowest patch.
  void OrderRadially(int a, std::vector<int>& halfpatches) const {
    const GridPoint& from = out_.arc_ends_[a].first;
    const int m = arc_axis_[a];
    auto angle = [&](int hp) {
      const PatchGeom& patch = patches_[hp >> 1];
      const int r = 3 - m - patch.axis;  // the axis along which the patch leaves the arc
      const bool positive = patch.rect.hi[r] > from[r];
      return (r == FirstInPlaneAxis(m) ? 0 : 1) + (positive ? 0 : 2);
    };
    std::sort(halfpatches.begin(), halfpatches.end(),
              [&](int x, int y) { return angle(x) < angle(y); });
    auto outside = std::find_if(halfpatches.begin(), halfpatches.end(),
                                [&](int hp) { return patches_[hp >> 1].blocks[hp & 1] < 0; });
    auto first = outside != halfpatches.end()
                     ? outside + 1
                     : std::min_element(halfpatches.begin(), halfpatches.end());
    if (first == halfpatches.end()) first = halfpatches.begin();
    std::rotate(halfpatches.begin(), first, halfpatches.end());
  }

  // Feature marks of the spec, then the ends of feature curves (upstream marks those nodes).
  absl::Status MarkFeatures() {
    for (const GridPoint& p : spec_.feature_nodes) {
      const int n = out_.NodeAt(p);
      if (n < 0) return Invalid("feature node ", PointString(p), " is not a node");
      proto_.mutable_nodes(n)->set_feature(true);
    }
    for (const auto& [a, b] : spec_.feature_arcs) {
      const std::vector<int> chain = out_.HalfarcChain(a, b);
      if (chain.empty()) {
        return Invalid("feature arc ", PointString(a), "-", PointString(b),
                       " is not a chain of arcs between two nodes");
      }
      for (int h : chain) {
        v1::Arc* arc = proto_.mutable_arcs(h >> 1);
        arc->set_feature(true);
        arc->set_critical(true);
      }
    }
    // The patches of each grid plane, so that a box looks only at its own plane's: with a scan
    // of every patch per box, sizing a 10^5-arc assembly100 mesh (tests/bench/large/
    // assembly_tmesh_generator.h, thousands of feature boxes) took 21.9 s CPU, with this 6.1 s.
    std::map<std::pair<int, int>, std::vector<int>> plane_patches;  // (axis, coordinate)
    if (!spec_.feature_patches.empty()) {
      for (size_t p = 0; p < patches_.size(); ++p) {
        const int axis = patches_[p].axis;
        plane_patches[{axis, patches_[p].rect.lo[axis]}].push_back(static_cast<int>(p));
      }
    }
    for (const GridBox& box : spec_.feature_patches) {
      const int axis = FlatAxis(box);
      if (axis < 0) {
        return Invalid("feature patch box ", PointString(box.lo), "-", PointString(box.hi),
                       " is not a rectangle");
      }
      int64_t area = 0;
      const auto plane = plane_patches.find({axis, box.lo[axis]});
      if (plane == plane_patches.end()) {
        return Invalid("feature patch box ", PointString(box.lo), "-", PointString(box.hi),
                       " is not a union of patches");
      }
      for (int p : plane->second) {
        const GridBox& rect = patches_[p].rect;
        bool inside = true;
        for (int k = 0; k < 3; ++k)
          inside = inside && box.lo[k] <= rect.lo[k] && rect.hi[k] <= box.hi[k];
        if (!inside) continue;
        area += Area(rect);
        v1::Patch* patch = proto_.mutable_patches(p);
        patch->set_feature(true);
        patch->set_critical(true);
      }
      if (area != Area(box)) {
        return Invalid("feature patch box ", PointString(box.lo), "-", PointString(box.hi),
                       " is not a union of patches");
      }
    }
    for (int n = 0; n < proto_.nodes_size(); ++n) {
      const int feature_arcs = CountIncident(n, [](const v1::Arc& arc) { return arc.feature(); });
      if (feature_arcs != 0 && feature_arcs != 2) proto_.mutable_nodes(n)->set_feature(true);
    }
    return absl::OkStatus();
  }

  // The axis on which a flat box has no extent, if it has exactly one such axis and lo <= hi.
  static int FlatAxis(const GridBox& box) {
    int axis = -1;
    for (int k = 0; k < 3; ++k) {
      if (box.lo[k] > box.hi[k]) return -1;
      if (box.lo[k] == box.hi[k]) {
        if (axis >= 0) return -1;
        axis = k;
      }
    }
    return axis;
  }

  static int64_t Area(const GridBox& rect) {
    int64_t area = 1;
    for (int k = 0; k < 3; ++k) {
      if (rect.hi[k] > rect.lo[k]) area *= rect.hi[k] - rect.lo[k];
    }
    return area;
  }

  template <typename Predicate>
  int CountIncident(int n, Predicate predicate) const {
    int count = 0;
    for (int h : proto_.nodes(n).outgoing_halfarcs())
      count += predicate(proto_.arcs(h >> 1)) ? 1 : 0;
    return count;
  }

  // Singular and feature types and the critical flag, by the rules of proto/README.md, section
  // Criticality (core/tmesh_criticality_checks.cc recomputes them the same way).
  absl::Status WriteNodeTypes() {
    std::vector<bool> arc_on_feature_patch(proto_.arcs_size(), false);
    std::vector<bool> node_on_feature_patch(proto_.nodes_size(), false);
    for (const v1::Patch& patch : proto_.patches()) {
      if (!patch.feature()) continue;
      for (int h : patch.halfarcs()) {
        arc_on_feature_patch[h >> 1] = true;
        node_on_feature_patch[proto_.arcs(h >> 1).from()] = true;
        node_on_feature_patch[proto_.arcs(h >> 1).to()] = true;
      }
    }
    for (int n = 0; n < proto_.nodes_size(); ++n) {
      v1::Node* node = proto_.mutable_nodes(n);
      int singular = 0, feature = 0;
      bool singular_non_feature = false, singular_off_feature_patches = false;
      for (int h : node->outgoing_halfarcs()) {
        const v1::Arc& arc = proto_.arcs(h >> 1);
        if (arc.feature()) ++feature;
        if (arc.singular() == 0) continue;
        ++singular;
        singular_non_feature = singular_non_feature || !arc.feature();
        singular_off_feature_patches =
            singular_off_feature_patches || !arc_on_feature_patch[h >> 1];
      }
      node->set_singular_type(singular == 0   ? v1::SingularType::REGULAR
                              : singular == 2 ? v1::SingularType::SEMI_SINGULAR
                                              : v1::SingularType::SINGULAR);
      v1::FeatureType::Value feature_type = v1::FeatureType::REGULAR;
      if (node->feature() || (feature != 0 && feature != 2)) {
        feature_type = v1::FeatureType::FEATURE;
      } else if (feature == 2) {
        feature_type = singular_non_feature ? v1::FeatureType::SEMI_FEATURE_SINGULAR_BRANCH
                                            : v1::FeatureType::SEMI_FEATURE;
      } else if (singular == 2 && node_on_feature_patch[n] && singular_off_feature_patches) {
        feature_type = v1::FeatureType::SEMI_FEATURE_SINGULAR_BRANCH;
      }
      node->set_feature_type(feature_type);
      node->set_critical(node->singular_type() == v1::SingularType::SINGULAR ||
                         feature_type == v1::FeatureType::FEATURE ||
                         feature_type == v1::FeatureType::SEMI_FEATURE_SINGULAR_BRANCH);
    }
    return absl::OkStatus();
  }

  absl::Status WriteBlocks() {
    patch_sides_of_block_.assign(num_blocks(), {});
    for (size_t p = 0; p < patches_.size(); ++p) {
      for (int x = 0; x < 2; ++x) {
        if (patches_[p].blocks[x] >= 0)
          patch_sides_of_block_[patches_[p].blocks[x]].push_back({p, x});
      }
    }
    for (int b = 0; b < num_blocks(); ++b) WriteBlock(b);
    return absl::OkStatus();
  }

  void WriteBlock(int b) {
    const Rotation rotation = rotation_[b];
    v1::Block* out = proto_.add_blocks();
    // Grid point of each corner, indexed by its corner code in the block's frame.
    std::array<GridPoint, kNumCorners> corner_point;
    for (int global = 0; global < kNumCorners; ++global) {
      GridPoint p;
      std::array<int64_t, 3> sign;
      for (int k = 0; k < 3; ++k) {
        const bool positive = (global & (1 << k)) != 0;
        p[k] = positive ? block(b).hi[k] : block(b).lo[k];
        sign[k] = positive ? 1 : -1;
      }
      const std::array<int64_t, 3> local = rotation.Apply(sign);
      int code = 0;
      for (int k = 0; k < 3; ++k) code |= local[k] > 0 ? 1 << k : 0;
      corner_point[code] = p;
    }
    // Corners and edges in upstream enum order of their keys.
    std::vector<std::pair<int, int>> corners;  // (key bits, corner code)
    for (int code = 0; code < kNumCorners; ++code)
      corners.push_back({SidesBits(code, {0, 1, 2}), code});
    std::sort(corners.begin(), corners.end());
    for (const auto& [bits, code] : corners) {
      v1::Corner* corner = out->add_corners();
      corner->set_corner(static_cast<v1::UVWDir>(bits));
      corner->set_node(out_.NodeAt(corner_point[code]));
    }
    std::vector<std::pair<int, std::pair<int, int>>> edges;  // (key bits, (low corner, axis))
    for (int axis = 0; axis < 3; ++axis) {
      const int o1 = axis == 0 ? 1 : 0, o2 = axis == 2 ? 1 : 2;
      for (int flags = 0; flags < 4; ++flags) {
        const int low = ((flags & 1) << o1) | (((flags >> 1) & 1) << o2);
        edges.push_back({SidesBits(low, {o1, o2}), {low, axis}});
      }
    }
    std::sort(edges.begin(), edges.end());
    for (const auto& [bits, edge] : edges) {
      const auto [low, axis] = edge;
      v1::Edge* out_edge = out->add_edges();
      out_edge->set_edge(static_cast<v1::UVWDir>(bits));
      for (int h : out_.HalfarcChain(corner_point[low], corner_point[low | (1 << axis)])) {
        out_edge->add_arcs(h >> 1);
        out_edge->add_halfarcs(h);
      }
      out_edge->set_ordered(true);
    }

    std::set<int> block_arcs;
    std::vector<int> halfpatches;
    for (Dir side : kAllDirs) {
      const Dir global_side = rotation.Inverse().Apply(side);
      const int k = AxisOf(global_side);
      GridBox face = block(b);
      face.lo[k] = face.hi[k] = IsNegative(global_side) ? block(b).lo[k] : block(b).hi[k];
      v1::Face* out_face = out->add_faces();
      out_face->set_side(DirToProto(side));
      std::set<int> inner_arcs, inner_nodes;
      auto strictly_inside = [&](const GridPoint& doubled) {
        for (int q : {FirstInPlaneAxis(k), SecondInPlaneAxis(k)}) {
          if (doubled[q] <= 2 * face.lo[q] || doubled[q] >= 2 * face.hi[q]) return false;
        }
        return true;
      };
      for (const auto& [p, x] : patch_sides_of_block_[b]) {
        if (patches_[p].FaceSide(x) != global_side) continue;
        out_face->add_patches(static_cast<int>(p));
        halfpatches.push_back(2 * static_cast<int>(p) + x);
        for (int h : proto_.patches(p).halfarcs()) {
          const auto& [from, to] = out_.arc_ends_[h >> 1];
          block_arcs.insert(h >> 1);
          const GridPoint mid = {from[0] + to[0], from[1] + to[1], from[2] + to[2]};
          if (strictly_inside(mid)) inner_arcs.insert(h >> 1);
          for (const GridPoint& end : {from, to}) {
            if (strictly_inside({2 * end[0], 2 * end[1], 2 * end[2]})) {
              inner_nodes.insert(out_.NodeAt(end));
            }
          }
        }
      }
      for (int a : inner_arcs) out_face->add_arcs(a);
      for (int n : inner_nodes) out_face->add_nodes(n);
    }
    std::sort(halfpatches.begin(), halfpatches.end());
    for (int hp : halfpatches) out->add_halfpatches(hp);
    out->set_self_adjacent(false);

    std::array<v1::DirectedArcs*, kNumDirs> by_dir;
    for (Dir d : kAllDirs) {
      by_dir[DirIndex(d)] = out->add_arcs_by_dir();
      by_dir[DirIndex(d)]->set_dir(DirToProto(d));
    }
    std::set<int> block_nodes;
    for (int a : block_arcs) {
      by_dir[DirIndex(rotation.Apply(MakeDir(arc_axis_[a], false)))]->add_arcs(a);
      block_nodes.insert(proto_.arcs(a).from());
      block_nodes.insert(proto_.arcs(a).to());
    }
    for (int n : block_nodes) {
      v1::NodeUvw* uvw = out->add_node_uvw();
      uvw->set_node(n);
      for (double x : BlockUvw(b, out_.node_points_[n])) uvw->add_uvw(x);
    }
  }

  // proto/README.md, section Critical entities: critical nodes, then links traced from them, then
  // cyclic links not reached from any critical node, then regions.
  absl::Status WriteCriticalEntities() {
    auto add_entity = [&](int dim, int from, int to) {
      v1::CriticalEntity* entity = proto_.add_critical_entities();
      entity->set_id(proto_.critical_entities_size() - 1);
      entity->set_dim(dim);
      entity->set_node_from(from);
      entity->set_node_to(to);
      return entity;
    };
    for (int n = 0; n < proto_.nodes_size(); ++n) {
      if (proto_.nodes(n).critical()) add_entity(0, n, n);
    }
    std::vector<bool> used(proto_.arcs_size(), false);
    auto head = [&](int h) {
      return (h & 1) ? proto_.arcs(h >> 1).from() : proto_.arcs(h >> 1).to();
    };
    // Follows critical arcs from halfarc h until a critical node or `stop` is reached.
    auto trace = [&](int start, int h, int stop) -> absl::StatusOr<std::vector<int>> {
      std::vector<int> chain = {h};
      used[h >> 1] = true;
      int at = head(h);
      while (!proto_.nodes(at).critical() && at != stop) {
        int next = -1;
        for (int out : proto_.nodes(at).outgoing_halfarcs()) {
          if (proto_.arcs(out >> 1).critical() && !used[out >> 1]) next = out;
        }
        if (next < 0) {
          return absl::InternalError(
              absl::StrCat("critical link from node ", start, " ends at non-critical node ", at));
        }
        chain.push_back(next);
        used[next >> 1] = true;
        at = head(next);
      }
      return chain;
    };
    auto add_link = [&](int start, const std::vector<int>& chain) {
      v1::CriticalEntity* link = add_entity(1, start, head(chain.back()));
      for (int h : chain) link->add_halfarcs(h);
    };
    for (int n = 0; n < proto_.nodes_size(); ++n) {
      if (!proto_.nodes(n).critical()) continue;
      for (int h : proto_.nodes(n).outgoing_halfarcs()) {
        if (!proto_.arcs(h >> 1).critical() || used[h >> 1]) continue;
        absl::StatusOr<std::vector<int>> chain = trace(n, h, -1);
        if (!chain.ok()) return chain.status();
        add_link(n, *chain);
      }
    }
    for (int a = 0; a < proto_.arcs_size(); ++a) {
      if (!proto_.arcs(a).critical() || used[a]) continue;
      const int start = proto_.arcs(a).from();
      absl::StatusOr<std::vector<int>> chain = trace(start, 2 * a, start);
      if (!chain.ok()) return chain.status();
      add_link(start, *chain);
    }
    // Regions: critical patches connected across non-critical arcs.
    std::vector<bool> assigned(proto_.patches_size(), false);
    for (int seed = 0; seed < proto_.patches_size(); ++seed) {
      if (!proto_.patches(seed).critical() || assigned[seed]) continue;
      std::set<int> patches = {seed}, boundary_arcs;
      std::vector<int> stack = {seed};
      assigned[seed] = true;
      while (!stack.empty()) {
        const int p = stack.back();
        stack.pop_back();
        for (int h : proto_.patches(p).halfarcs()) {
          const v1::Arc& arc = proto_.arcs(h >> 1);
          if (arc.critical()) {
            boundary_arcs.insert(h >> 1);
            continue;
          }
          for (int hp : arc.halfpatches()) {
            const int q = hp >> 1;
            if (!proto_.patches(q).critical() || assigned[q]) continue;
            assigned[q] = true;
            patches.insert(q);
            stack.push_back(q);
          }
        }
      }
      v1::CriticalEntity* region = add_entity(2, -1, -1);
      for (int p : patches) region->add_patches(p);
      for (int a : boundary_arcs) region->add_boundary_arcs(a);
    }
    return absl::OkStatus();
  }

  absl::Status WriteLevelsAndStats() {
    proto_.set_format_version(1);
    proto_.set_name(spec_.name);
    proto_.set_source("synthetic");
    proto_.set_generator("ispq tests/support/grid_tmesh_builder (global grid of boxes)");
    proto_.set_variant(3);
    v1::FeaturesPresent* present = proto_.mutable_features_present();
    for (const v1::Node& node : proto_.nodes())
      present->set_nodes(present->nodes() || node.feature());
    for (const v1::Arc& arc : proto_.arcs()) present->set_arcs(present->arcs() || arc.feature());
    for (const v1::Patch& patch : proto_.patches()) {
      present->set_patches(present->patches() || patch.feature());
    }

    std::vector<double> lengths;
    for (const v1::Arc& arc : proto_.arcs()) lengths.push_back(arc.length());
    for (int percent : kLevelPercents) {
      v1::Level* level = proto_.add_levels();
      level->set_percent(percent);
      level->set_scaling(*ScalingForPercent(lengths, percent));
    }

    v1::FileStats* stats = proto_.mutable_stats();
    stats->set_nodes(proto_.nodes_size());
    stats->set_arcs(proto_.arcs_size());
    stats->set_patches(proto_.patches_size());
    stats->set_blocks(proto_.blocks_size());
    for (const v1::Node& node : proto_.nodes()) {
      stats->set_critical_nodes(stats->critical_nodes() + (node.critical() ? 1 : 0));
    }
    for (const v1::Arc& arc : proto_.arcs()) {
      stats->set_critical_arcs(stats->critical_arcs() + (arc.critical() ? 1 : 0));
      stats->set_singular_arcs(stats->singular_arcs() + (arc.singular() != 0 ? 1 : 0));
    }
    double max_residual = 0;
    for (const v1::Patch& patch : proto_.patches()) {
      stats->set_critical_patches(stats->critical_patches() + (patch.critical() ? 1 : 0));
      stats->set_boundary_patches(stats->boundary_patches() + (patch.boundary() ? 1 : 0));
      std::array<double, kNumDirs> side_length = {};
      for (const v1::DirectedHalfarcs& side : patch.halfarcs_by_dir()) {
        const int d = DirIndex(*DirFromUpstreamBits(side.dir()));
        for (int h : side.halfarcs()) side_length[d] += proto_.arcs(h >> 1).length();
      }
      for (int axis = 0; axis < 3; ++axis) {
        const double pos = side_length[2 * axis], neg = side_length[2 * axis + 1];
        if (pos > 0) max_residual = std::max(max_residual, std::abs(pos - neg) / pos);
      }
    }
    std::array<int, 3> by_dim = {0, 0, 0};
    for (const v1::CriticalEntity& entity : proto_.critical_entities()) ++by_dim[entity.dim()];
    for (int count : by_dim) stats->add_critical_entities_by_dim(count);
    stats->set_min_arc_length(*std::min_element(lengths.begin(), lengths.end()));
    stats->set_max_relative_side_residual(max_residual);
    return absl::OkStatus();
  }

  const GridTMeshSpec& spec_;
  GridTMesh out_;
  v1::TMesh& proto_;
  std::array<std::vector<double>, 3> coord_;  // continuous coordinate of each grid index
  std::vector<Rotation> rotation_;            // per block: global frame -> block frame
  std::array<int, 3> cells_ = {0, 0, 0};      // the grid's extent in cells
  std::vector<int> cell_block_;               // per cell (u fastest, then v, then w): its block
  std::vector<PatchGeom> patches_;            // per patch id
  // Per block, its (patch, side) pairs in ascending patch order.
  std::vector<std::vector<std::pair<size_t, int>>> patch_sides_of_block_;
  std::map<std::array<int, 3>, std::vector<int>> lines_;  // LineKey -> sorted node coordinates
  std::vector<int> arc_axis_;
  std::vector<int> arc_quarter_turns_;  // quarter turns of block material around each arc
  std::vector<bool> node_boundary_;
};

int GridTMesh::NodeAt(const GridPoint& p) const {
  const auto it = node_index_.find(p);
  return it == node_index_.end() ? -1 : it->second;
}

int GridTMesh::ArcBetween(const GridPoint& a, const GridPoint& b) const {
  const auto [from, to] = std::minmax(a, b, PointLess);
  const auto it = arc_index_.find({from, to});
  return it == arc_index_.end() ? -1 : it->second;
}

int GridTMesh::HalfarcFromTo(const GridPoint& from, const GridPoint& to) const {
  const int a = ArcBetween(from, to);
  if (a < 0) return -1;
  return 2 * a + (arc_ends_[a].first == from ? 0 : 1);
}

std::vector<int> GridTMesh::HalfarcChain(const GridPoint& from, const GridPoint& to) const {
  const int axis = SegmentAxis(from, to);
  if (axis < 0 || NodeAt(from) < 0 || NodeAt(to) < 0) return {};
  const int step = to[axis] > from[axis] ? 1 : -1;
  std::vector<int> chain;
  GridPoint at = from, previous = from;
  while (at != to) {
    at[axis] += step;
    if (NodeAt(at) < 0) continue;
    const int h = HalfarcFromTo(previous, at);
    if (h < 0) return {};
    chain.push_back(h);
    previous = at;
  }
  return chain;
}

int GridTMesh::PatchAt(const GridBox& rect) const {
  const auto it = patch_index_.find({rect.lo, rect.hi});
  return it == patch_index_.end() ? -1 : it->second;
}

std::vector<int64_t> GridTMesh::QFromIntervals(
    const std::array<std::vector<int64_t>, 3>& intervals) const {
  std::vector<int64_t> q;
  q.reserve(arc_ends_.size());
  for (const auto& [from, to] : arc_ends_) {
    int64_t sum = 0;
    for (int k = 0; k < 3; ++k) {
      for (int i = from[k]; i < to[k]; ++i) sum += intervals[k][i];
    }
    q.push_back(sum);
  }
  return q;
}

absl::StatusOr<GridTMesh> BuildGridTMesh(const GridTMeshSpec& spec) {
  return GridTMeshBuilder(spec).Build();
}

GridTMesh BuildGridTMeshOrDie(const GridTMeshSpec& spec) {
  absl::StatusOr<GridTMesh> grid = BuildGridTMesh(spec);
  if (!grid.ok()) {
    std::cerr << "invalid grid spec " << spec.name << ": " << grid.status() << "\n";
    std::abort();
  }
  return *std::move(grid);
}

GridTMeshSpec RingAroundAHole() {
  GridTMeshSpec spec;
  spec.name = "ring";
  for (int x = 0; x < 3; ++x) {
    for (int y = 0; y < 3; ++y) {
      if (x != 1 || y != 1) spec.blocks.push_back(GridBox{{x, y, 0}, {x + 1, y + 1, 1}});
    }
  }
  return spec;
}

GridTMeshSpec ExtrudeLayout(const GridLayout2D& layout) {
  GridTMeshSpec spec;
  spec.name = layout.name;
  for (const GridRect& rect : layout.blocks) {
    spec.blocks.push_back({{rect.lo[0], rect.lo[1], 0}, {rect.hi[0], rect.hi[1], 1}});
  }
  spec.spacing = {layout.spacing[0], layout.spacing[1], {layout.layer_height}};
  for (const GridPoint2& p : layout.feature_nodes) {
    spec.feature_arcs.push_back({{p[0], p[1], 0}, {p[0], p[1], 1}});
  }
  for (const auto& [a, b] : layout.feature_arcs) {
    spec.feature_patches.push_back({{std::min(a[0], b[0]), std::min(a[1], b[1]), 0},
                                    {std::max(a[0], b[0]), std::max(a[1], b[1]), 1}});
  }
  return spec;
}

absl::StatusOr<std::string> TMeshToJson(const v1::TMesh& mesh) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;  // the format writes every key
  std::string json;
  const auto status = google::protobuf::util::MessageToJsonString(mesh, &json, options);
  if (!status.ok()) {
    return absl::InternalError(absl::StrCat("cannot write JSON: ", std::string(status.message())));
  }
  return json;
}

}  // namespace ispq::testing
