// SPDX-License-Identifier: Apache-2.0
#include "tests/bench/large/large_tmesh_generator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "core/rotation.h"

namespace ispq::bench {
namespace {

using testing::GridBox;
using testing::GridPoint;

// Which cells are material and which block owns each, during the tiling.
class CellGrid {
 public:
  explicit CellGrid(const LargePartShape& s)
      : n_{s.cells_u, s.cells_v, s.cells_w}, solid_(Size(), 1), owner_(Size(), -1) {}

  int extent(int k) const { return n_[k]; }
  bool Inside(const GridPoint& c) const {
    for (int k = 0; k < 3; ++k) {
      if (c[k] < 0 || c[k] >= n_[k]) return false;
    }
    return true;
  }
  bool Free(const GridPoint& c) const { return Inside(c) && solid_[At(c)] && owner_[At(c)] < 0; }
  void Remove(const GridBox& box) {
    for (int z = box.lo[2]; z < box.hi[2]; ++z) {
      for (int y = box.lo[1]; y < box.hi[1]; ++y) {
        for (int x = box.lo[0]; x < box.hi[0]; ++x) solid_[At({x, y, z})] = 0;
      }
    }
  }
  bool BoxFree(const GridBox& box) const {
    for (int z = box.lo[2]; z < box.hi[2]; ++z) {
      for (int y = box.lo[1]; y < box.hi[1]; ++y) {
        for (int x = box.lo[0]; x < box.hi[0]; ++x) {
          if (!Free({x, y, z})) return false;
        }
      }
    }
    return true;
  }
  void Claim(const GridBox& box, int block) {
    for (int z = box.lo[2]; z < box.hi[2]; ++z) {
      for (int y = box.lo[1]; y < box.hi[1]; ++y) {
        for (int x = box.lo[0]; x < box.hi[0]; ++x) owner_[At({x, y, z})] = block;
      }
    }
  }

 private:
  size_t Size() const { return static_cast<size_t>(n_[0]) * n_[1] * n_[2]; }
  size_t At(const GridPoint& c) const {
    return (static_cast<size_t>(c[2]) * n_[1] + c[1]) * n_[0] + c[0];
  }

  std::array<int, 3> n_;
  std::vector<uint8_t> solid_;
  std::vector<int> owner_;
};

// The feature zone: the plane w = fw over v < fv, bounded by the feature curve v = fv on it. No
// block of the zone crosses the plane, and no block touching it crosses v = fv, so that the zone
// is a union of patches and the curve a chain of arcs; every other block may cross both planes,
// which keeps the parts above and below coupled.
struct Cuts {
  int feature_w;
  int feature_v;
};

// The notch (a quarter of the u and v extents, along the whole height, at high v), tunnels
// through the height away from the feature zone v < fv + 2, and a blind pocket from the top.
void CarveHoles(const Cuts& cuts, CellGrid& grid, std::mt19937_64& random) {
  const int nu = grid.extent(0), nv = grid.extent(1), nw = grid.extent(2);
  grid.Remove({{0, nv - std::max(1, nv / 4), 0}, {std::max(1, nu / 4), nv, nw}});
  const int first_v = cuts.feature_v + 3;
  for (int v = first_v; v + 2 < nv - nv / 4 - 1; v += 6) {
    for (int u = 2 + static_cast<int>(random() % 3); u + 4 < nu; u += 7) {
      grid.Remove({{u, v, 0}, {u + 2, v + 2, nw}});
    }
  }
  if (nw >= 4 && nu >= 8) grid.Remove({{nu - 5, 1, nw / 2}, {nu - 2, 3, nw}});
}

// Largest box from cell c with extents at most `want` that is free and crosses no cut.
GridBox GrowBlock(const GridPoint& c, std::array<int, 3> want, const Cuts& cuts,
                  const CellGrid& grid) {
  if (c[1] < cuts.feature_v) {
    if (c[2] < cuts.feature_w) want[2] = std::min(want[2], cuts.feature_w - c[2]);
    // Blocks are at most 3 cells high: only these can reach the plane from below.
    if (c[2] >= cuts.feature_w - 3 && c[2] <= cuts.feature_w) {
      want[1] = std::min(want[1], cuts.feature_v - c[1]);
    }
  }
  GridBox box{c, {c[0] + 1, c[1] + 1, c[2] + 1}};
  for (int k = 0; k < 3; ++k) {
    for (int d = want[k]; d > 1; --d) {
      GridBox grown = box;
      grown.hi[k] = c[k] + d;
      if (grid.BoxFree(grown)) {
        box = grown;
        break;
      }
    }
  }
  return box;
}

std::vector<double> JitteredSpacing(int n, std::mt19937_64& random) {
  std::uniform_real_distribution<double> log_length(std::log(0.3), std::log(3.0));
  std::vector<double> spacing(n);
  for (double& s : spacing) s = std::exp(log_length(random));
  return spacing;
}

}  // namespace

const char* LargeFamilyName(LargeFamily family) {
  switch (family) {
    case LargeFamily::kSingleSubproblem:
      return "single";
    case LargeFamily::kSlabs:
      return "slabs";
    case LargeFamily::kRotated:
      return "rotated";
    case LargeFamily::kAssembly16:
      return "assembly16";
    case LargeFamily::kAssembly50:
      return "assembly50";
    case LargeFamily::kAssembly100:
      return "assembly100";
  }
  return "?";
}

std::optional<LargeFamily> LargeFamilyFromName(const std::string& name) {
  for (LargeFamily f :
       {LargeFamily::kSingleSubproblem, LargeFamily::kSlabs, LargeFamily::kRotated,
        LargeFamily::kAssembly16, LargeFamily::kAssembly50, LargeFamily::kAssembly100}) {
    if (name == LargeFamilyName(f)) return f;
  }
  return std::nullopt;
}

std::optional<AssemblyDensity> AssemblyDensityOf(LargeFamily family) {
  AssemblyDensity d;
  d.name = LargeFamilyName(family);
  switch (family) {
    case LargeFamily::kAssembly16:
      d.part_min = 3, d.part_max = 6, d.block_max = 3, d.feature_share = 0.35;
      d.voids_per_part = 0.85, d.edge_share = 0;
      return d;
    case LargeFamily::kAssembly50:
      d.part_min = 2, d.part_max = 4, d.block_max = 3, d.feature_share = 0.7;
      d.voids_per_part = 2, d.edge_share = 0.5;
      return d;
    case LargeFamily::kAssembly100:  // parts of 2 cells a side, every interface a feature
      d.part_min = 2, d.part_max = 2, d.block_max = 3, d.feature_share = 1;
      d.voids_per_part = 3, d.edge_share = 1;
      return d;
    default:
      return std::nullopt;
  }
}

testing::GridTMeshSpec LargePartSpec(LargeFamily family, const LargePartShape& shape,
                                     uint64_t seed) {
  std::mt19937_64 random(seed);
  testing::GridTMeshSpec spec;
  spec.name = std::string("large-") + LargeFamilyName(family);
  for (int k = 0; k < 3; ++k) {
    spec.spacing[k] =
        JitteredSpacing(k == 0 ? shape.cells_u : (k == 1 ? shape.cells_v : shape.cells_w), random);
  }
  CellGrid grid(shape);
  const Cuts cuts{std::max(1, shape.cells_w / 2), std::max(1, shape.cells_v / 4)};
  CarveHoles(cuts, grid, random);
  std::uniform_int_distribution<int> size(1, 3);
  for (int z = 0; z < shape.cells_w; ++z) {
    for (int y = 0; y < shape.cells_v; ++y) {
      for (int x = 0; x < shape.cells_u; ++x) {
        if (!grid.Free({x, y, z})) continue;
        std::array<int, 3> want = {size(random), size(random), size(random)};
        if (family == LargeFamily::kSlabs) want[2] = 1;
        const GridBox box = GrowBlock({x, y, z}, want, cuts, grid);
        grid.Claim(box, static_cast<int>(spec.blocks.size()));
        spec.blocks.push_back(box);
      }
    }
  }
  if (family == LargeFamily::kRotated) {
    std::uniform_int_distribution<int> rotation(0, Rotation::kCount - 1);
    for (int b = 0; b < static_cast<int>(spec.blocks.size()); ++b) {
      spec.block_rotations.push_back({b, rotation(random)});
    }
  }
  // The feature zone: the plane w = fw over v < fv is solid, bounded by the curve v = fv.
  spec.feature_patches.push_back(
      {{0, 0, cuts.feature_w}, {shape.cells_u, cuts.feature_v, cuts.feature_w}});
  spec.feature_arcs.push_back(
      {{0, cuts.feature_v, cuts.feature_w}, {shape.cells_u, cuts.feature_v, cuts.feature_w}});
  return spec;
}

absl::StatusOr<testing::GridTMesh> BuildLargeTMesh(LargeFamily family, int target_arcs,
                                                   uint64_t seed) {
  if (const std::optional<AssemblyDensity> density = AssemblyDensityOf(family)) {
    return BuildAssemblyTMesh(*density, target_arcs, seed);
  }
  // Arcs grow with the cell count; proportions 2 : 1.5 : 1.
  auto shape_for = [](double cells) {
    const double unit = std::cbrt(cells / 3.0);
    return LargePartShape{std::max(3, static_cast<int>(std::lround(2 * unit))),
                          std::max(3, static_cast<int>(std::lround(1.5 * unit))),
                          std::max(2, static_cast<int>(std::lround(unit)))};
  };
  double cells = std::max(18.0, target_arcs / 2.0);
  absl::StatusOr<testing::GridTMesh> mesh;
  for (int attempt = 0; attempt < 4; ++attempt) {
    const LargePartShape shape = shape_for(cells);
    mesh = absl::UnknownError("not built");  // frees the previous attempt first
    mesh = testing::BuildGridTMesh(LargePartSpec(family, shape, seed));
    if (!mesh.ok()) return mesh.status();
    const double arcs = mesh->proto().arcs_size();
    if (std::abs(arcs - target_arcs) <= 0.03 * target_arcs) break;
    cells *= target_arcs / arcs;
  }
  return mesh;
}

}  // namespace ispq::bench
