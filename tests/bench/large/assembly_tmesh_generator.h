// SPDX-License-Identifier: Apache-2.0
// Feature-dense synthetic T-meshes for the scaling benchmark: polycube-like CAD assemblies whose
// critical entities per arc match the real T-meshes at every size (issue 26, item 1).
//
// The families of large_tmesh_generator.h have one feature plane and one feature curve per mesh,
// so their critical entities per arc fall as the part grows (0.0065 at 87.6k arcs), while the 62
// real T-meshes have 0.16-2.17 (median 0.55). An assembly keeps its features in proportion to its
// volume: the cell grid is packed with *parts* (boxes of a few cells per axis, placed greedily so
// that their faces never line up: T-junctions everywhere), each part is tiled by blocks of 1 to a
// few cells that never cross the part's faces, and every part is machined:
//
//   - voids carved out of it (pockets and blind holes opening onto one face, through holes,
//     slots and notches along a whole axis, closed cavities), each at least one cell away from any
//     other void, so that the volume stays manifold; a void opening onto a neighbour part is
//     closed by that part's face, as in an assembly;
//   - a share of the interfaces between two parts marked as feature surfaces, with feature
//     curves along each such interface's border (the CAD face borders);
//   - a share of the part's own edges marked as feature curves.
//
// The count of parts, voids and feature interfaces grows with the volume, so a family's density
// stays nearly constant from 1k to 10^6 arcs, and a growth exponent measures the algorithm rather
// than a mesh that gets sparser. Consistency still runs across every part (blocks meet parts
// through T-junctions on the interfaces), so the mesh is one subproblem per axis: decomposition
// does not hide the cost. The density presets (AssemblyDensityOf) are tuned by measurement with
// `ispq stats --json`; see tests/bench/large/results/README.md for the statistics they give.
//
// Not part of the product: only benchmarks and their unit test use it.
#ifndef ISPQ_TESTS_BENCH_LARGE_ASSEMBLY_TMESH_GENERATOR_H_
#define ISPQ_TESTS_BENCH_LARGE_ASSEMBLY_TMESH_GENERATOR_H_

#include <array>
#include <cstdint>
#include <string>

#include "absl/status/statusor.h"
#include "tests/support/grid_tmesh_builder.h"

namespace ispq::bench {

// The knobs of one density level.
struct AssemblyDensity {
  std::string name;
  int part_min = 3, part_max = 8;  // part extents, cells per axis (clipped at the grid's end)
  int block_max = 3;               // block extents within a part: 1..block_max cells per axis
  double feature_share = 0.35;     // share of part interfaces that are feature surfaces
  double voids_per_part = 1.0;     // mean number of voids carved per part
  double edge_share = 0.0;         // share of part edges (left whole by voids) that are feature
                                   // curves
};

// The grid's extent in cells.
using AssemblyShape = std::array<int, 3>;

// The grid spec of an assembly of this shape.
testing::GridTMeshSpec AssemblySpec(const AssemblyDensity& density, const AssemblyShape& shape,
                                    uint64_t seed);

// An assembly of about `target_arcs` arcs (within a few percent). Large targets are sized from a
// smaller pilot build, so that at most two builds of the full size are made and never two at
// once.
absl::StatusOr<testing::GridTMesh> BuildAssemblyTMesh(const AssemblyDensity& density,
                                                      int target_arcs, uint64_t seed);

}  // namespace ispq::bench

#endif  // ISPQ_TESTS_BENCH_LARGE_ASSEMBLY_TMESH_GENERATOR_H_
