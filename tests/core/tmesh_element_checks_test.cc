// SPDX-License-Identifier: Apache-2.0
// The rules one node, arc, block or level satisfies on its own, on plain inputs: a valid element
// passes, and each broken rule is reported naming the element and the value that breaks it.
#include "core/tmesh_element_checks.h"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/resolution_levels.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

constexpr FeaturesPresent kAllFeatures = {.nodes = true, .arcs = true, .patches = true};
constexpr FeaturesPresent kNoFeatures = {};

// A regular interior arc 0 -> 1 on two halfpatches.
class ValidArc {
 public:
  ArcInput Get() const {
    ArcInput arc;
    arc.from = 0;
    arc.to = 1;
    arc.length = 2.5;
    arc.halfpatches = halfpatches_;
    return arc;
  }

 private:
  std::vector<HalfpatchId> halfpatches_ = {0, 3};
};

TEST(TMeshElementChecksTest, SizesNeedOneOfEachKindAndFitHalfIds) {
  EXPECT_TRUE(CheckSizes({1, 1, 1, 1}).ok());
  EXPECT_EQ(CheckSizes({0, 1, 1, 1}).message(), "the mesh has no nodes");
  EXPECT_EQ(CheckSizes({1, 1, 1, 0}).message(), "the mesh has no blocks");
  // Halfarc ids are 2a + 1: the largest arc count whose halfarcs fit int32 is accepted.
  const int largest = std::numeric_limits<int32_t>::max() / 2;
  EXPECT_TRUE(CheckSizes({1, largest, 1, 1}).ok());
  EXPECT_EQ(CheckSizes({1, largest + 1, 1, 1}).message(),
            "the mesh has too many arcs: " + std::to_string(largest + 1));
  EXPECT_EQ(CheckSizes({1, 1, largest + 1, 1}).code(), absl::StatusCode::kInvalidArgument);
}

TEST(TMeshElementChecksTest, AFeatureNodeNeedsNodeFeaturesPresent) {
  NodeInput feature;
  feature.feature = true;
  EXPECT_TRUE(CheckNode(4, feature, kAllFeatures).ok());
  EXPECT_TRUE(CheckNode(4, NodeInput{}, kNoFeatures).ok());
  EXPECT_EQ(CheckNode(4, feature, {.nodes = false, .arcs = true, .patches = true}).message(),
            "node 4: marked feature but featuresPresent.nodes is false");
}

TEST(TMeshElementChecksTest, AValidArcPasses) {
  const ValidArc valid;
  EXPECT_TRUE(CheckArc(7, valid.Get(), kNoFeatures).ok());
  ArcInput singular_feature = valid.Get();
  singular_feature.singular = -4;
  singular_feature.feature = true;
  singular_feature.critical = true;
  EXPECT_TRUE(CheckArc(7, singular_feature, kAllFeatures).ok());
}

TEST(TMeshElementChecksTest, ArcLoopAndLengthsAreNamed) {
  const ValidArc valid;
  ArcInput loop = valid.Get();
  loop.to = loop.from;
  EXPECT_EQ(CheckArc(7, loop, kNoFeatures).message(), "arc 7: starts and ends at node 0");
  for (const double length : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    ArcInput arc = valid.Get();
    arc.length = length;
    const absl::Status status = CheckArc(7, arc, kNoFeatures);
    EXPECT_EQ(status.code(), absl::StatusCode::kInvalidArgument) << length;
    EXPECT_THAT(std::string(status.message()), HasSubstr("is not a positive finite number"));
    EXPECT_THAT(std::string(status.message()), HasSubstr("arc 7: length "));
  }
}

TEST(TMeshElementChecksTest, SingularMarkOutsideMinusFourToFourIsRefused) {
  const ValidArc valid;
  for (const int mark : {-5, 5, 100}) {
    ArcInput arc = valid.Get();
    arc.singular = mark;
    arc.critical = true;
    EXPECT_EQ(CheckArc(2, arc, kNoFeatures).message(),
              "arc 2: singular mark " + std::to_string(mark) + " is out of range -4..4");
  }
}

// critical == (singular != 0 || feature), both ways.
TEST(TMeshElementChecksTest, ArcCriticalFlagFollowsItsMarks) {
  const ValidArc valid;
  ArcInput invented = valid.Get();
  invented.critical = true;
  EXPECT_EQ(CheckArc(3, invented, kAllFeatures).message(),
            "arc 3: critical flag 1 contradicts singular != 0 || feature");
  ArcInput singular_not_critical = valid.Get();
  singular_not_critical.singular = 1;
  EXPECT_EQ(CheckArc(3, singular_not_critical, kAllFeatures).message(),
            "arc 3: critical flag 0 contradicts singular != 0 || feature");
  ArcInput feature_not_critical = valid.Get();
  feature_not_critical.feature = true;
  EXPECT_THAT(std::string(CheckArc(3, feature_not_critical, kAllFeatures).message()),
              HasSubstr("arc 3: critical flag 0"));
}

TEST(TMeshElementChecksTest, ArcFeatureNeedsArcFeaturesAndAnArcNeedsAPatch) {
  const ValidArc valid;
  ArcInput feature = valid.Get();
  feature.feature = true;
  feature.critical = true;
  EXPECT_EQ(CheckArc(9, feature, {.nodes = true, .arcs = false, .patches = true}).message(),
            "arc 9: marked feature but featuresPresent.arcs is false");
  ArcInput alone = valid.Get();
  alone.halfpatches = {};
  EXPECT_EQ(CheckArc(9, alone, kNoFeatures).message(), "arc 9: lies on no patch");
}

TEST(TMeshElementChecksTest, ABlockNamesEachArcAndNodeOnce) {
  BlockInput block;
  block.arcs = {{1, Dir::kPosU}, {4, Dir::kNegV}, {6, Dir::kPosW}};
  block.node_uvw = {{0, {0, 0, 0}}, {2, {1, 0, 0}}, {5, {1, 1, 0}}};
  EXPECT_TRUE(CheckBlock(3, block).ok());

  BlockInput twice_arc = block;
  twice_arc.arcs.insert(twice_arc.arcs.begin() + 2, {4, Dir::kPosU});
  EXPECT_EQ(CheckBlock(3, twice_arc).message(), "block 3: arc 4 appears twice in arcsByDir");

  BlockInput twice_node = block;
  twice_node.node_uvw.push_back({5, {1, 1, 1}});
  EXPECT_EQ(CheckBlock(3, twice_node).message(), "block 3: node 5 appears twice in nodeUvw");
}

TEST(TMeshElementChecksTest, ALevelIsAFormatPercentWithItsScaling) {
  const std::vector<double> lengths = {0.5, 1.0, 2.0, 4.0, 8.0};
  for (int i = 0; i < static_cast<int>(kLevelPercents.size()); ++i) {
    const int percent = kLevelPercents[i];
    EXPECT_TRUE(CheckLevel(i, {percent, *ScalingForPercent(lengths, percent)}, lengths).ok())
        << percent;
  }
  EXPECT_THAT(std::string(CheckLevel(2, {3, 1.0}, lengths).message()),
              HasSubstr("level 2: percent 3"));
  const double s50 = *ScalingForPercent(lengths, 50);
  EXPECT_THAT(std::string(CheckLevel(6, {50, 2 * s50}, lengths).message()),
              HasSubstr("level 6: scaling "));
  EXPECT_THAT(std::string(CheckLevel(6, {50, 2 * s50}, lengths).message()),
              HasSubstr(" for 50% should be "));
  EXPECT_FALSE(CheckLevel(6, {50, std::nan("")}, lengths).ok());
  // Within the relative 1e-9 the stored scaling still matches.
  EXPECT_TRUE(CheckLevel(6, {50, s50 * (1 + 1e-12)}, lengths).ok());
}

}  // namespace
}  // namespace ispq
