// SPDX-License-Identifier: Apache-2.0
#include "tests/bench/large/assembly_tmesh_generator.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <random>
#include <utility>
#include <vector>

namespace ispq::bench {
namespace {

using testing::GridBox;
using testing::GridPoint;

// Per fine cell of the grid: its part and whether it was carved away.
class AssemblyGrid {
 public:
  explicit AssemblyGrid(const AssemblyShape& n) : n_(n), part_(Size(), -1), carved_(Size(), 0) {}

  int extent(int k) const { return n_[k]; }
  GridBox box() const { return {{0, 0, 0}, n_}; }
  bool Inside(const GridPoint& c) const {
    for (int k = 0; k < 3; ++k) {
      if (c[k] < 0 || c[k] >= n_[k]) return false;
    }
    return true;
  }
  int part(const GridPoint& c) const { return part_[At(c)]; }
  bool carved(const GridPoint& c) const { return carved_[At(c)] != 0; }
  void set_part(const GridPoint& c, int p) { part_[At(c)] = p; }
  void carve(const GridPoint& c) { carved_[At(c)] = 1; }

 private:
  size_t Size() const { return static_cast<size_t>(n_[0]) * n_[1] * n_[2]; }
  size_t At(const GridPoint& c) const {
    return (static_cast<size_t>(c[2]) * n_[1] + c[1]) * n_[0] + c[0];
  }

  AssemblyShape n_;
  std::vector<int32_t> part_;
  std::vector<uint8_t> carved_;
};

template <typename Visit>
void ForEachCell(const GridBox& box, Visit visit) {
  for (int z = box.lo[2]; z < box.hi[2]; ++z) {
    for (int y = box.lo[1]; y < box.hi[1]; ++y) {
      for (int x = box.lo[0]; x < box.hi[0]; ++x) visit(GridPoint{x, y, z});
    }
  }
}

template <typename Predicate>
bool AllCells(const GridBox& box, Predicate predicate) {
  for (int z = box.lo[2]; z < box.hi[2]; ++z) {
    for (int y = box.lo[1]; y < box.hi[1]; ++y) {
      for (int x = box.lo[0]; x < box.hi[0]; ++x) {
        if (!predicate(GridPoint{x, y, z})) return false;
      }
    }
  }
  return true;
}

// The largest box from cell c with extents at most `want`, grown along u, then v, then w, whose
// cells all satisfy `free` (c itself must).
template <typename Free>
GridBox GrowBox(const GridPoint& c, const std::array<int, 3>& want, Free free) {
  GridBox box{c, {c[0] + 1, c[1] + 1, c[2] + 1}};
  for (int k = 0; k < 3; ++k) {
    for (int d = want[k]; d > 1; --d) {
      GridBox grown = box;
      grown.hi[k] = c[k] + d;
      if (AllCells(grown, free)) {
        box = grown;
        break;
      }
    }
  }
  return box;
}

int Uniform(std::mt19937_64& random, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(random);
}

// A part: its box in the grid and its own lattice of cells, in which its voids and blocks are
// laid out. cuts[k] lists the grid coordinates of its cell boundaries along axis k, from box.lo[k]
// to box.hi[k]. Cells are 1 to 3 grid units wide, drawn per part, so that the lattices of two
// parts rarely line up: where they meet, every interface is cut by both, and arcs that consistency
// forces equal (bundles) stay within a part or two instead of running along a grid plane through
// the whole assembly (with one lattice for all parts, arcs per bundle grew from 13 at 1k arcs to
// 54 at 100k in the densest family).
struct Part {
  GridBox box;
  std::array<std::vector<int>, 3> cuts;

  int cells(int k) const { return static_cast<int>(cuts[k].size()) - 1; }
  GridBox CellBox() const { return {{0, 0, 0}, {cells(0), cells(1), cells(2)}}; }
  // The grid box of a box of this part's cells.
  GridBox GridBoxOf(const GridBox& cell_box) const {
    GridBox box;
    for (int k = 0; k < 3; ++k) {
      box.lo[k] = cuts[k][cell_box.lo[k]];
      box.hi[k] = cuts[k][cell_box.hi[k]];
    }
    return box;
  }
  size_t CellIndex(const GridPoint& c) const {
    return (static_cast<size_t>(c[2]) * cells(1) + c[1]) * cells(0) + c[0];
  }
};

constexpr int kMaxCellWidth = 3;  // grid units per part cell

// Packs the grid with parts by splitting it recursively: a box longer than part_max cells on
// some axis is cut across one such axis (drawn at random) at a random place that leaves both
// sides at least part_min cells (at 2 grid units per cell, the mean cell width, give or take one
// unit). The cuts of two neighbouring boxes are independent, so part faces rarely line up
// (T-junctions everywhere), and the parts' sizes do not depend on the grid's: a greedy packing
// that grew parts from the lowest free cell instead made them smaller the more layers it stacked
// (parts per grid cell 0.0025 at 30k arcs, 0.0040 at 300k, and critical entities per arc 0.17 and
// 0.21 with them).
std::vector<Part> PackParts(const AssemblyDensity& density, AssemblyGrid& grid,
                            std::mt19937_64& random) {
  // Cells are 2 grid units wide on average; one unit of slack either way keeps the cuts of
  // neighbouring boxes from falling on the same planes when part_min == part_max (with exactly 4
  // units, the v arcs of a 5k-arc assembly100 fell into three and four subproblems for seeds 1
  // and 7).
  const int min_units = 2 * density.part_min - 1, max_units = 2 * density.part_max + 1;
  std::vector<Part> parts;
  std::vector<GridBox> stack = {grid.box()};
  // A cut through the whole grid would split the arcs along its normal into two subproblems: no
  // patch crosses it, so nothing ties the arcs on one side to those on the other (a 5k-arc
  // assembly50 had a fourth subproblem of 18% of the bundles). So the grid is first cut as a
  // pinwheel in (u, v): four boxes around a fifth, no straight cut through all of them; every
  // later cut runs through one box only, and blocks of the boxes beside it cross its plane.
  const int nu = grid.extent(0), nv = grid.extent(1), nw = grid.extent(2);
  if (nu >= 3 * min_units && nv >= 3 * min_units && nw > max_units) {
    const int a = Uniform(random, min_units, nu - 2 * min_units);
    const int b = Uniform(random, a + min_units, nu - min_units);
    const int c = Uniform(random, min_units, nv - 2 * min_units);
    const int d = Uniform(random, c + min_units, nv - min_units);
    stack = {GridBox{{a, c, 0}, {b, d, nw}}, GridBox{{0, c, 0}, {a, nv, nw}},
             GridBox{{a, d, 0}, {nu, nv, nw}}, GridBox{{b, 0, 0}, {nu, d, nw}},
             GridBox{{0, 0, 0}, {b, c, nw}}};
  }
  while (!stack.empty()) {
    const GridBox box = stack.back();
    stack.pop_back();
    std::vector<int> long_axes;
    for (int k = 0; k < 3; ++k) {
      if (box.hi[k] - box.lo[k] > max_units) long_axes.push_back(k);
    }
    if (!long_axes.empty()) {
      const int k = long_axes[Uniform(random, 0, static_cast<int>(long_axes.size()) - 1)];
      const int extent = box.hi[k] - box.lo[k];
      // Halves if both sides cannot have part_min cells (part_max < 2 part_min).
      const int cut = extent >= 2 * min_units
                          ? Uniform(random, box.lo[k] + min_units, box.hi[k] - min_units)
                          : box.lo[k] + extent / 2;
      GridBox low = box, high = box;
      low.hi[k] = high.lo[k] = cut;
      stack.push_back(high);
      stack.push_back(low);
      continue;
    }
    Part part;
    part.box = box;
    for (int k = 0; k < 3; ++k) {
      // Cells of random widths, the last one cut short where the part ends.
      part.cuts[k] = {box.lo[k]};
      while (part.cuts[k].back() < box.hi[k]) {
        part.cuts[k].push_back(
            std::min(part.cuts[k].back() + Uniform(random, 1, kMaxCellWidth), box.hi[k]));
      }
    }
    const int id = static_cast<int>(parts.size());
    ForEachCell(part.box, [&](const GridPoint& x) { grid.set_part(x, id); });
    parts.push_back(std::move(part));
  }
  return parts;
}

// An interval [lo, hi) of a part's extent e along one axis, relative to its low end.
using Interval = std::pair<int, int>;

std::optional<Interval> Whole(int e) { return Interval{0, e}; }
// Away from both ends by at least one cell, of size at most `max_size`.
std::optional<Interval> Inner(int e, int max_size, std::mt19937_64& random) {
  if (e < 3) return std::nullopt;
  const int size = Uniform(random, 1, std::min(max_size, e - 2));
  const int lo = Uniform(random, 1, e - 1 - size);
  return Interval{lo, lo + size};
}
// From one end (chosen at random), at least one cell short of the other.
std::optional<Interval> FromEnd(int e, int min_size, std::mt19937_64& random) {
  if (e < 2 || min_size > e - 1) return std::nullopt;
  const int size = Uniform(random, min_size, e - 1);
  return Uniform(random, 0, 1) == 0 ? Interval{0, size} : Interval{e - size, e};
}

enum class VoidKind { kPocket, kBlindHole, kThroughHole, kSlot, kNotch, kCavity };
constexpr int kNumVoidKinds = 6;

// A void of this kind in the part, along a random axis, or none if the part is too thin for it.
// Pockets and blind holes open onto one face of the part, through holes onto two opposite ones,
// slots onto three, notches onto four (along a whole edge), cavities onto none.
std::optional<GridBox> VoidIn(const GridBox& part, VoidKind kind, std::mt19937_64& random) {
  std::array<int, 3> axes = {0, 1, 2};
  std::shuffle(axes.begin(), axes.end(), random);
  std::array<int, 3> e;
  for (int i = 0; i < 3; ++i) e[i] = part.hi[axes[i]] - part.lo[axes[i]];
  std::array<std::optional<Interval>, 3> span;
  switch (kind) {
    case VoidKind::kPocket:
      span = {FromEnd(e[0], 1, random), Inner(e[1], e[1], random), Inner(e[2], e[2], random)};
      break;
    case VoidKind::kBlindHole:
      span = {FromEnd(e[0], e[0] - 1, random), Inner(e[1], 1, random), Inner(e[2], 1, random)};
      break;
    case VoidKind::kThroughHole:
      span = {Whole(e[0]), Inner(e[1], 1, random), Inner(e[2], 1, random)};
      break;
    case VoidKind::kSlot:
      span = {Whole(e[0]), Inner(e[1], e[1], random), FromEnd(e[2], 1, random)};
      break;
    case VoidKind::kNotch:
      span = {Whole(e[0]), FromEnd(e[1], 1, random), FromEnd(e[2], 1, random)};
      break;
    case VoidKind::kCavity:
      span = {Inner(e[0], e[0], random), Inner(e[1], e[1], random), Inner(e[2], e[2], random)};
      break;
  }
  GridBox box;
  for (int i = 0; i < 3; ++i) {
    if (!span[i].has_value()) return std::nullopt;
    box.lo[axes[i]] = part.lo[axes[i]] + span[i]->first;
    box.hi[axes[i]] = part.lo[axes[i]] + span[i]->second;
  }
  return box;
}

// Carves voids out of the parts (in their own cells), tiles the rest of every part by blocks of
// 1..block_max cells per axis into spec.blocks, and marks a share of the part edges that the voids
// left whole as feature curves (CAD edges of the part). A void must keep a grid cell of material
// between itself and every other void, also diagonally, so that the voids are disjoint closed
// boxes and the volume stays manifold (grid_tmesh_builder.h rejects blocks meeting only along an
// edge); a candidate that comes too close to an earlier void is dropped.
void CarveTileAndMarkEdges(const AssemblyDensity& density, const std::vector<Part>& parts,
                           AssemblyGrid& grid, std::mt19937_64& random,
                           testing::GridTMeshSpec& spec) {
  const int whole = static_cast<int>(std::floor(density.voids_per_part));
  std::bernoulli_distribution extra(density.voids_per_part - whole);
  std::bernoulli_distribution edge_feature(density.edge_share);
  for (const Part& part : parts) {
    const GridBox cells = part.CellBox();
    std::vector<uint8_t> carved(static_cast<size_t>(cells.hi[0]) * cells.hi[1] * cells.hi[2], 0);
    const int count = whole + (extra(random) ? 1 : 0);
    // A candidate too close to an earlier void is drawn again, a few times, so that dense
    // presets get about the voids they ask for.
    for (int i = 0, tries = 0; i < count && tries < 4 * count; ++tries) {
      const auto kind = static_cast<VoidKind>(Uniform(random, 0, kNumVoidKinds - 1));
      const std::optional<GridBox> cell_box = VoidIn(cells, kind, random);
      if (!cell_box.has_value()) continue;
      const GridBox box = part.GridBoxOf(*cell_box);
      GridBox margin = box;
      for (int k = 0; k < 3; ++k) {
        margin.lo[k] = std::max(0, margin.lo[k] - 1);
        margin.hi[k] = std::min(grid.extent(k), margin.hi[k] + 1);
      }
      if (!AllCells(margin, [&](const GridPoint& c) { return !grid.carved(c); })) continue;
      ForEachCell(box, [&](const GridPoint& c) { grid.carve(c); });
      ForEachCell(*cell_box, [&](const GridPoint& c) { carved[part.CellIndex(c)] = 1; });
      ++i;
    }
    std::vector<uint8_t> taken = carved;
    ForEachCell(cells, [&](const GridPoint& c) {
      if (taken[part.CellIndex(c)]) return;
      std::array<int, 3> want;
      for (int& w : want) w = Uniform(random, 1, density.block_max);
      const GridBox box = GrowBox(c, want, [&](const GridPoint& x) {
        for (int k = 0; k < 3; ++k) {
          if (x[k] >= cells.hi[k]) return false;
        }
        return !taken[part.CellIndex(x)];
      });
      ForEachCell(box, [&](const GridPoint& x) { taken[part.CellIndex(x)] = 1; });
      spec.blocks.push_back(part.GridBoxOf(box));
    });
    // An edge whose row of cells is all material is a chain of block edges between two block
    // corners, as the builder needs a feature curve to be.
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      for (int side = 0; side < 4; ++side) {
        GridBox row = cells;
        row.lo[k1] = (side & 1) ? cells.hi[k1] - 1 : 0;
        row.lo[k2] = (side & 2) ? cells.hi[k2] - 1 : 0;
        row.hi[k1] = row.lo[k1] + 1;
        row.hi[k2] = row.lo[k2] + 1;
        if (!edge_feature(random) ||
            !AllCells(row, [&](const GridPoint& c) { return !carved[part.CellIndex(c)]; })) {
          continue;
        }
        GridPoint from = part.box.lo;
        from[k1] = (side & 1) ? part.box.hi[k1] : part.box.lo[k1];
        from[k2] = (side & 2) ? part.box.hi[k2] : part.box.lo[k2];
        GridPoint to = from;
        to[k] = part.box.hi[k];
        spec.feature_arcs.push_back({from, to});
      }
    }
  }
}

// The interfaces between parts: for every part and each axis, the rectangles its high face
// shares with the parts beyond it. Each is exactly a union of patches: every block lies in one
// part, and where a void on one side leaves the other's face bare, the bare face is boundary
// patches of the same rectangle (voids are a grid unit apart, so never on both sides at once).
std::vector<GridBox> PartInterfaces(const std::vector<Part>& parts, const AssemblyGrid& grid) {
  std::vector<GridBox> interfaces;
  for (const Part& p : parts) {
    const GridBox& part = p.box;
    for (int k = 0; k < 3; ++k) {
      const int plane = part.hi[k];
      if (plane >= grid.extent(k)) continue;
      GridBox face = part;
      face.lo[k] = plane;
      face.hi[k] = plane + 1;
      std::vector<int> across;
      ForEachCell(face, [&](const GridPoint& c) { across.push_back(grid.part(c)); });
      std::sort(across.begin(), across.end());
      across.erase(std::unique(across.begin(), across.end()), across.end());
      for (int other : across) {
        GridBox rect = part;
        rect.lo[k] = rect.hi[k] = plane;
        for (int q = 0; q < 3; ++q) {
          if (q == k) continue;
          rect.lo[q] = std::max(part.lo[q], parts[other].box.lo[q]);
          rect.hi[q] = std::min(part.hi[q], parts[other].box.hi[q]);
        }
        interfaces.push_back(rect);
      }
    }
  }
  return interfaces;
}

// Marks a rectangle as a feature surface and its border as four feature curves.
void MarkFeatureInterface(const GridBox& rect, testing::GridTMeshSpec& spec) {
  spec.feature_patches.push_back(rect);
  int flat = 0;
  while (rect.lo[flat] != rect.hi[flat]) ++flat;
  const int qi = (flat + 1) % 3, qj = (flat + 2) % 3;
  auto corner = [&](bool hi_i, bool hi_j) {
    GridPoint p = rect.lo;
    p[qi] = hi_i ? rect.hi[qi] : rect.lo[qi];
    p[qj] = hi_j ? rect.hi[qj] : rect.lo[qj];
    return p;
  };
  spec.feature_arcs.push_back({corner(false, false), corner(true, false)});
  spec.feature_arcs.push_back({corner(false, true), corner(true, true)});
  spec.feature_arcs.push_back({corner(false, false), corner(false, true)});
  spec.feature_arcs.push_back({corner(true, false), corner(true, true)});
}

std::vector<double> JitteredSpacing(int n, std::mt19937_64& random) {
  std::uniform_real_distribution<double> log_length(std::log(0.3), std::log(3.0));
  std::vector<double> spacing(n);
  for (double& s : spacing) s = std::exp(log_length(random));
  return spacing;
}

// Grid proportions 2 : 1.5 : 1, as the other families.
AssemblyShape ShapeForCells(double cells) {
  const double unit = std::cbrt(cells / 3.0);
  return {std::max(3, static_cast<int>(std::lround(2 * unit))),
          std::max(3, static_cast<int>(std::lround(1.5 * unit))),
          std::max(2, static_cast<int>(std::lround(unit)))};
}

double CellCount(const AssemblyShape& shape) { return 1.0 * shape[0] * shape[1] * shape[2]; }

}  // namespace

testing::GridTMeshSpec AssemblySpec(const AssemblyDensity& density, const AssemblyShape& shape,
                                    uint64_t seed) {
  std::mt19937_64 random(seed);
  testing::GridTMeshSpec spec;
  spec.name = density.name;
  for (int k = 0; k < 3; ++k) spec.spacing[k] = JitteredSpacing(shape[k], random);
  AssemblyGrid grid(shape);
  const std::vector<Part> parts = PackParts(density, grid, random);
  CarveTileAndMarkEdges(density, parts, grid, random, spec);
  std::bernoulli_distribution feature(density.feature_share);
  for (const GridBox& rect : PartInterfaces(parts, grid)) {
    if (feature(random)) MarkFeatureInterface(rect, spec);
  }
  return spec;
}

absl::StatusOr<testing::GridTMesh> BuildAssemblyTMesh(const AssemblyDensity& density,
                                                      int target_arcs, uint64_t seed) {
  // Arcs per grid cell are nearly constant within a family (features scale with the volume), but
  // a new shape is a new layout with a few percent more or fewer arcs per cell, and rescaling the
  // whole shape went back and forth at small sizes (3k arcs asked, 2,264 made after 8 builds). So
  // after a first build only the longest extent moves, to untried values, and small targets keep
  // the closest of up to 8 builds. Large ones are sized from a pilot at 30k arcs (within 3% at
  // 300k and 10^6 arcs) and keep only their latest build, so that a 10^6-arc mesh is never held
  // twice.
  constexpr int kPilotArcs = 30000;
  constexpr int kLargeArcs = 100000;
  const bool large = target_arcs > kLargeArcs;
  double arcs_per_cell = 0.35;
  auto build = [&](const AssemblyShape& shape) {
    return testing::BuildGridTMesh(AssemblySpec(density, shape, seed));
  };
  if (large) {
    const AssemblyShape shape = ShapeForCells(kPilotArcs / arcs_per_cell);
    const absl::StatusOr<testing::GridTMesh> pilot = build(shape);
    if (!pilot.ok()) return pilot.status();
    arcs_per_cell = pilot->proto().arcs_size() / CellCount(shape);
  }
  AssemblyShape shape = ShapeForCells(target_arcs / arcs_per_cell);
  std::vector<int> tried;
  absl::StatusOr<testing::GridTMesh> best = absl::UnknownError("not built");
  double best_error = std::numeric_limits<double>::infinity();
  for (int attempt = 0; attempt < (large ? 3 : 8); ++attempt) {
    if (large) best = absl::UnknownError("not built");  // frees the previous build first
    absl::StatusOr<testing::GridTMesh> mesh = build(shape);
    if (!mesh.ok()) return mesh.status();
    tried.push_back(shape[0]);
    const double arcs = mesh->proto().arcs_size();
    const double error = std::abs(arcs - target_arcs) / target_arcs;
    if (large || error < best_error) {
      best = std::move(mesh);
      best_error = error;
    }
    if (error <= 0.03) break;
    arcs_per_cell = arcs / CellCount(shape);
    const int step = arcs < target_arcs ? 1 : -1;
    int u = std::max(3, static_cast<int>(std::lround(target_arcs / arcs_per_cell /
                                                     (1.0 * shape[1] * shape[2]))));
    while (std::find(tried.begin(), tried.end(), u) != tried.end()) u += step;
    if (u < 3) break;
    shape[0] = u;
  }
  return best;
}

}  // namespace ispq::bench
