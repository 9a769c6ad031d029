// SPDX-License-Identifier: Apache-2.0
// The memory budget's estimates (server/memory/memory_estimates.h): the solve size admission
// derives from a mesh's stats and a job's options, the solver's working memory as the formula in
// the header has it (what grows it, and the cap on each LP), and what a retained job holds.
// Whether the solver estimate holds the heap a solve really takes is measured in
// tests/server/memory/solver_memory_test.cc, as is the mesh estimate against a validated mesh.
#include "server/memory/memory_estimates.h"

#include <vector>

#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "core/proto/quantization_proto.h"
#include "gtest/gtest.h"
#include "tests/support/test_data.h"
#include "tests/support/tmesh_copies.h"

namespace ispq::server {
namespace {

v1::MeshStats Stats(int arcs, int bundles, int subproblems) {
  v1::MeshStats stats;
  stats.set_arcs(arcs);
  stats.set_bundles(bundles);
  stats.set_subproblems(subproblems);
  return stats;
}

TEST(MemoryEstimatesTest, TheSolveSizeIsTheMeshsAndOneLpPerSubproblem) {
  const SolveSize size = SolveSizeOf(Stats(3000, 200, 7), QuantizeOptions());
  EXPECT_EQ(size.arcs, 3000);
  EXPECT_EQ(size.bundles, 200);
  EXPECT_EQ(size.subproblems, 7);
  EXPECT_FALSE(size.exact);
}

TEST(MemoryEstimatesTest, WithoutDecompositionTheSolveKeepsOneLp) {
  QuantizeOptions options;
  options.decompose = false;
  EXPECT_EQ(SolveSizeOf(Stats(3000, 200, 7), options).subproblems, 1);
  EXPECT_EQ(SolveSizeOf(Stats(0, 0, 0), options).subproblems, 0) << "an empty mesh has no LP";
}

TEST(MemoryEstimatesTest, ExactModeIsTheExactMethod) {
  QuantizeOptions options;
  options.method = QuantizationMethod::kExact;
  EXPECT_TRUE(SolveSizeOf(Stats(12, 3, 1), options).exact);
}

TEST(MemoryEstimatesTest, EveryPartOfTheSolveSizeAddsMemory) {
  const SolveSize base{.arcs = 1000, .bundles = 50, .subproblems = 10};
  const int64_t bytes = SolverBytes(base);
  EXPECT_GT(bytes, kSolverBaseBytes + kJobOverheadBytes);

  SolveSize more_arcs = base;
  more_arcs.arcs += 1;
  EXPECT_EQ(SolverBytes(more_arcs) - bytes, kSolverBytesPerArc);
  SolveSize more_bundles = base;  // 5 bundles per LP: far below an LP's cap
  more_bundles.bundles += 1;
  EXPECT_EQ(SolverBytes(more_bundles) - bytes, kSolverBytesPerBundle + kLpBytesPerBundle);
  SolveSize more_lps = base;
  more_lps.subproblems += 1;
  EXPECT_EQ(SolverBytes(more_lps) - bytes, kLpBaseBytes);
  SolveSize exact = base;
  exact.exact = true;
  EXPECT_EQ(SolverBytes(exact) - bytes, kExactBaseBytes + kExactBytesPerArc * base.arcs);
}

// However the bundles are shared out, each LP is counted at most at kLpMaxBytes: beyond that,
// a bundle adds its own tables only.
TEST(MemoryEstimatesTest, EachLpIsCountedAtMostAtItsCap) {
  const SolveSize one_lp{.arcs = 100000, .bundles = 5000, .subproblems = 1};
  SolveSize one_more_bundle = one_lp;
  one_more_bundle.bundles += 1;
  EXPECT_EQ(SolverBytes(one_more_bundle) - SolverBytes(one_lp), kSolverBytesPerBundle);
  EXPECT_EQ(SolverBytes(one_lp), kJobOverheadBytes + kSolverBaseBytes +
                                     kSolverBytesPerArc * one_lp.arcs +
                                     kSolverBytesPerBundle * one_lp.bundles + kLpMaxBytes);
  // The same mesh in two LPs may hold two LPs' worth.
  SolveSize two_lps = one_lp;
  two_lps.subproblems = 2;
  EXPECT_EQ(SolverBytes(two_lps) - SolverBytes(one_lp), kLpMaxBytes);
}

// k disjoint copies of a real mesh: a solve k times as large. With decomposition each copy adds
// the same (its own subproblems, each with its LP); in one LP a copy adds less once that LP is
// at its cap, but never nothing.
TEST(MemoryEstimatesTest, TheEstimateGrowsWithTheMesh) {
  const v1::TMesh notch =
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  for (const bool decompose : {true, false}) {
    SCOPED_TRACE(decompose ? "decomposed" : "one LP");
    std::vector<int64_t> bytes;  // by copies - 1
    for (int copies = 1; copies <= 4; ++copies) {
      const TMesh mesh = testing::TMeshOrDie(testing::DisjointCopies(notch, copies));
      v1::QuantizationOptions request;
      request.mutable_scaling()->set_level_percent(25);
      request.set_decompose(decompose);
      const absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(request, mesh);
      ASSERT_TRUE(options.ok()) << options.status();
      bytes.push_back(SolverBytes(SolveSizeOf(MeshStatsToProto(ComputeMeshStats(mesh)), *options)));
    }
    for (size_t i = 1; i < bytes.size(); ++i) {
      EXPECT_GT(bytes[i], bytes[i - 1]) << i + 1 << " copies";
      if (decompose) {
        EXPECT_EQ(bytes[i] - bytes[i - 1], bytes[1] - bytes[0]);
      }
    }
  }
}

TEST(MemoryEstimatesTest, AMeshTakesTwiceItsWireSizeAndTheJobsOwnObjects) {
  EXPECT_EQ(MeshBytes(0), kJobOverheadBytes);
  EXPECT_EQ(MeshBytes(1 << 20) - MeshBytes(0), 2 << 20);
}

// A failed job holds its own objects; a finished one its result too, which grows with its q.
TEST(MemoryEstimatesTest, ARetainedJobHoldsItsResult) {
  EXPECT_EQ(RetainedJobBytes(nullptr), kJobOverheadBytes);
  v1::QuantizationResult small;
  small.set_mesh_name("cube");
  for (int i = 0; i < 12; ++i) small.add_q(1);
  v1::QuantizationResult large = small;
  for (int i = 0; i < 100000; ++i) large.add_q(3);
  EXPECT_GT(RetainedJobBytes(&small), kJobOverheadBytes);
  EXPECT_GE(RetainedJobBytes(&large) - RetainedJobBytes(&small), 4 * 100000);
  EXPECT_GE(RetainedJobBytes(&large),
            kJobOverheadBytes + static_cast<int64_t>(large.ByteSizeLong()));
}

}  // namespace
}  // namespace ispq::server
