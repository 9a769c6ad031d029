// SPDX-License-Identifier: Apache-2.0
// The rules one patch satisfies on its own, on the inputs of real patches of a small grid mesh
// (two blocks side by side, the shared wall 2 long along v and 1 along w): every patch as built
// passes, and each broken rule is reported naming the patch.
#include "core/tmesh_patch_checks.h"

#include <string>
#include <utility>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

constexpr FeaturesPresent kNoFeatures = {};
constexpr double kTolerance = 1e-6;

class TMeshPatchChecksTest : public ::testing::Test {
 protected:
  TMeshPatchChecksTest() {
    testing::GridTMeshSpec spec;
    spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
    spec.spacing = {{{1.0, 1.0}, {2.0}, {1.0}}};
    // Block 1 in a rotated frame, so that the wall has a non-identity transition.
    spec.block_rotations = {{1, 5}};
    absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(spec);
    EXPECT_TRUE(grid.ok()) << grid.status();
    grid_ = *std::move(grid);
    mesh_ = testing::TMeshOrDie(grid_.proto());
    wall_ = grid_.PatchAt({{1, 0, 0}, {1, 1, 1}});
    outer_ = grid_.PatchAt({{0, 0, 0}, {0, 1, 1}});
  }

  // The input the decoder would hand the builder for patch p, read back from the model.
  PatchInput InputOf(PatchId p) const {
    PatchInput patch;
    patch.blocks = {mesh_.patch_block(p, 0), mesh_.patch_block(p, 1)};
    patch.face_sides = {mesh_.patch_face_side(p, 0), mesh_.patch_face_side(p, 1)};
    patch.rotation = mesh_.patch_rotation(p);
    patch.feature = mesh_.patch_feature(p);
    patch.boundary = mesh_.patch_boundary(p);
    patch.critical = mesh_.patch_critical(p);
    patch.cycle = mesh_.patch_cycle(p);
    patch.ref_block = mesh_.patch_ref_block(p);
    for (int i = 0; i < 4; ++i) {
      const PatchSide side = mesh_.patch_side(p, i);
      patch.sides[i] = {side.dir, side.halfarcs};
    }
    return patch;
  }

  std::string Check(PatchId p, const PatchInput& patch, double tolerance = kTolerance) const {
    const absl::Status status = CheckPatch(p, patch, mesh_, kNoFeatures, tolerance);
    if (!status.ok()) {
      EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument);
    }
    return std::string(status.message());
  }

  // The wall's sides with the directions of sides 1 and 2 exchanged: side 0 (length a) is now
  // opposite a side of length b; still two opposite pairs of contiguous runs.
  PatchInput WallWithSidesOfDifferentLengthsOpposite() const {
    PatchInput patch = InputOf(wall_);
    std::swap(patch.sides[1].dir, patch.sides[2].dir);
    return patch;
  }

  testing::GridTMesh grid_;
  TMesh mesh_;
  PatchId wall_ = kNoId;
  PatchId outer_ = kNoId;
};

TEST_F(TMeshPatchChecksTest, EveryBuiltPatchPasses) {
  ASSERT_NE(wall_, kNoId);
  ASSERT_NE(outer_, kNoId);
  ASSERT_FALSE(mesh_.patch_rotation(wall_).IsIdentity());
  for (PatchId p = 0; p < mesh_.num_patches(); ++p) EXPECT_EQ(Check(p, InputOf(p)), "") << p;
}

TEST_F(TMeshPatchChecksTest, BlocksAndFlagsAgree) {
  const std::string wall = "patch " + std::to_string(wall_) + ": ";
  PatchInput nowhere = InputOf(wall_);
  nowhere.blocks = {kNoId, kNoId};
  EXPECT_EQ(Check(wall_, nowhere), wall + "has no block on either side");

  PatchInput self_adjacent = InputOf(wall_);
  self_adjacent.blocks[1] = self_adjacent.blocks[0];
  EXPECT_EQ(Check(wall_, self_adjacent),
            wall + "block " + std::to_string(self_adjacent.blocks[0]) +
                " is on both sides (self-adjacent blocks are not supported)");

  PatchInput claims_boundary = InputOf(wall_);
  claims_boundary.boundary = claims_boundary.critical = true;
  EXPECT_EQ(Check(wall_, claims_boundary), wall + "boundary flag 1 contradicts its blocks");

  PatchInput feature = InputOf(wall_);
  feature.feature = feature.critical = true;
  EXPECT_EQ(Check(wall_, feature), wall + "marked feature but featuresPresent.patches is false");
  EXPECT_EQ(CheckPatch(wall_, feature, mesh_, {.nodes = false, .arcs = false, .patches = true},
                       kTolerance),
            absl::OkStatus());

  PatchInput critical = InputOf(wall_);
  critical.critical = true;
  EXPECT_EQ(Check(wall_, critical), wall + "critical flag contradicts boundary || feature");

  const std::string outer = "patch " + std::to_string(outer_) + ": ";
  PatchInput not_critical = InputOf(outer_);
  not_critical.critical = false;
  EXPECT_EQ(Check(outer_, not_critical), outer + "critical flag contradicts boundary || feature");
  PatchInput rotated = InputOf(outer_);
  rotated.rotation = Rotation::FromIndex(5);
  EXPECT_EQ(Check(outer_, rotated), outer + "boundary patch with a non-identity transition");
}

TEST_F(TMeshPatchChecksTest, CycleIsAClosedChainOfFourOrMoreDistinctArcs) {
  const std::string wall = "patch " + std::to_string(wall_) + ": ";
  const PatchInput valid = InputOf(wall_);
  const std::vector<HalfarcId> cycle(valid.cycle.begin(), valid.cycle.end());
  ASSERT_EQ(cycle.size(), 4u);

  PatchInput short_cycle = valid;
  short_cycle.cycle = std::span<const HalfarcId>(cycle).first(3);
  EXPECT_EQ(Check(wall_, short_cycle), wall + "cycle has 3 halfarcs, at least 4 needed");

  std::vector<HalfarcId> swapped = cycle;
  std::swap(swapped[0], swapped[1]);
  PatchInput open = valid;
  open.cycle = swapped;
  EXPECT_THAT(Check(wall_, open), HasSubstr(wall + "cycle is not closed: halfarc "));

  // Out along one arc and back, twice: closed, but arc-wise a doubled segment.
  const std::vector<HalfarcId> back_and_forth = {cycle[0], cycle[0] ^ 1, cycle[0], cycle[0] ^ 1};
  PatchInput doubled = valid;
  doubled.cycle = back_and_forth;
  EXPECT_EQ(Check(wall_, doubled), wall + "cycle uses an arc twice");

  PatchInput other_ref = valid;
  other_ref.ref_block = valid.blocks[1];
  EXPECT_EQ(Check(wall_, other_ref), wall + "refBlock " + std::to_string(valid.blocks[1]) +
                                         " should be " + std::to_string(valid.blocks[0]));
  // A boundary patch whose only block is on side 1 refers to that block.
  PatchInput flipped = InputOf(outer_);
  flipped.blocks = {kNoId, flipped.blocks[0]};
  EXPECT_EQ(Check(outer_, flipped), "");
}

TEST_F(TMeshPatchChecksTest, SidesAreFourContiguousRunsInOppositePairs) {
  const std::string wall = "patch " + std::to_string(wall_) + ": ";
  const PatchInput valid = InputOf(wall_);

  PatchInput same_dir = valid;
  same_dir.sides[1].dir = same_dir.sides[0].dir;
  EXPECT_EQ(Check(wall_, same_dir),
            wall + "direction " + DirName(valid.sides[0].dir) + " used by two sides");

  PatchInput empty = valid;
  empty.sides[2].halfarcs = {};
  EXPECT_EQ(Check(wall_, empty), wall + "side " + DirName(valid.sides[2].dir) + " is empty");

  // A halfarc of the wall's cycle run backwards is not in the cycle.
  const HalfarcId reversed = valid.sides[3].halfarcs[0] ^ 1;
  PatchInput foreign = valid;
  foreign.sides[3].halfarcs = {&reversed, 1};
  EXPECT_EQ(Check(wall_, foreign), wall + "side " + DirName(valid.sides[3].dir) + " halfarc " +
                                       std::to_string(reversed) + " is not in the cycle");

  // Two halfarcs of the cycle that do not follow each other.
  const std::vector<HalfarcId> gap = {valid.cycle[0], valid.cycle[2]};
  PatchInput broken_run = valid;
  broken_run.sides[0].halfarcs = gap;
  EXPECT_THAT(Check(wall_, broken_run), HasSubstr("is not a contiguous run of the cycle"));

  // The side starting at the cycle's first halfarc takes the next one too: 5 halfarcs in sides
  // for a cycle of 4.
  const std::vector<HalfarcId> both = {valid.cycle[0], valid.cycle[1]};
  PatchInput overlapping = valid;
  for (PatchSideInput& side : overlapping.sides) {
    if (side.halfarcs[0] == valid.cycle[0]) side.halfarcs = both;
  }
  EXPECT_EQ(Check(wall_, overlapping), wall + "sides do not partition the cycle");

  // Four distinct directions, but on three axes: not two opposite pairs.
  const int a = AxisOf(valid.sides[0].dir);
  int b = a;
  for (const PatchSideInput& side : valid.sides) {
    if (AxisOf(side.dir) != a) b = AxisOf(side.dir);
  }
  ASSERT_NE(a, b);
  PatchInput three_axes = valid;
  for (PatchSideInput& side : three_axes.sides) {
    if (side.dir == Opposite(valid.sides[0].dir)) side.dir = MakeDir(3 - a - b, false);
  }
  EXPECT_EQ(Check(wall_, three_axes), wall + "sides are not two pairs of opposite directions");
}

TEST_F(TMeshPatchChecksTest, OppositeSidesHaveEqualLengthsUpToARelativeTolerance) {
  const std::string wall = "patch " + std::to_string(wall_) + ": ";
  const PatchInput mixed = WallWithSidesOfDifferentLengthsOpposite();
  const std::string message = Check(wall_, mixed);
  EXPECT_THAT(message, HasSubstr(wall + "side "));
  EXPECT_THAT(message, HasSubstr(" has continuous length "));
  // Lengths 1 and 2 (in some order): |1 - 2| = 1 is 50 % of the longer one.
  EXPECT_THAT(Check(wall_, mixed, 0.49), HasSubstr("has continuous length"));
  EXPECT_EQ(Check(wall_, mixed, 0.51), "");
}

}  // namespace
}  // namespace ispq
