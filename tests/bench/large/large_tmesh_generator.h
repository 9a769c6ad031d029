// SPDX-License-Identifier: Apache-2.0
// Large synthetic T-meshes for the scaling benchmark: connected polycube-like parts built on the
// grid builder (tests/support/grid_tmesh_builder.h), deterministic for a seed.
//
// A part is a box of cells with jittered spacings (target lengths varying about 10x), a notch
// along one vertical edge, vertical tunnels and a blind pocket; its cells are tiled by blocks of
// random sizes (1 to 3 cells per axis), so T-junctions are everywhere. A feature plane and a
// feature curve on it are marked (blocks never cross them). Families:
//   kSingleSubproblem  blocks of every size: the tiling couples every axis, one subproblem;
//   kSlabs             blocks one cell high: every layer's vertical arcs form their own
//                      subproblem beside the coupled horizontal ones;
//   kRotated           as kSingleSubproblem, every block in a random frame, so that every
//                      interior patch carries a transition.
// These have a fixed number of features, so their critical entities per arc fall with the size
// (0.0065 at 87.6k arcs). The assembly families (assembly_tmesh_generator.h) keep the density of
// real T-meshes at every size:
//   kAssembly16, kAssembly50, kAssembly100   about 0.16, 0.5 and 1.0 critical entities per arc.
// Not part of the product: only benchmarks use it.
#ifndef ISPQ_TESTS_BENCH_LARGE_LARGE_TMESH_GENERATOR_H_
#define ISPQ_TESTS_BENCH_LARGE_LARGE_TMESH_GENERATOR_H_

#include <cstdint>
#include <optional>
#include <string>

#include "absl/status/statusor.h"
#include "tests/bench/large/assembly_tmesh_generator.h"
#include "tests/support/grid_tmesh_builder.h"

namespace ispq::bench {

enum class LargeFamily {
  kSingleSubproblem,
  kSlabs,
  kRotated,
  kAssembly16,
  kAssembly50,
  kAssembly100
};

const char* LargeFamilyName(LargeFamily family);
std::optional<LargeFamily> LargeFamilyFromName(const std::string& name);

struct LargePartShape {
  int cells_u = 8, cells_v = 6, cells_w = 4;  // the bounding box in cells
};

// The assembly families' density presets; nullopt for the other families.
std::optional<AssemblyDensity> AssemblyDensityOf(LargeFamily family);

// The grid spec of a part with this shape (not for the assembly families).
testing::GridTMeshSpec LargePartSpec(LargeFamily family, const LargePartShape& shape,
                                     uint64_t seed);

// A part of about `target_arcs` arcs (within a few percent): the shape is scaled from a first
// build until the arc count fits.
absl::StatusOr<testing::GridTMesh> BuildLargeTMesh(LargeFamily family, int target_arcs,
                                                   uint64_t seed);

}  // namespace ispq::bench

#endif  // ISPQ_TESTS_BENCH_LARGE_LARGE_TMESH_GENERATOR_H_
