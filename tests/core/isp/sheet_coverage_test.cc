// SPDX-License-Identifier: Apache-2.0
// Which thorough-pass checks a non-improving sheet answers, and for how long.
#include "core/isp/sheet_coverage.h"

#include <cstdint>
#include <optional>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;
using ::testing::Optional;

std::optional<std::vector<BundleId>> Bundles(const std::optional<SheetCoverage::Answer>& answer) {
  if (!answer.has_value()) return std::nullopt;
  return std::vector<BundleId>(answer->bundles.begin(), answer->bundles.end());
}

IntegerSheet Sheet(std::vector<BundleId> bundles, std::vector<int64_t> deltas) {
  IntegerSheet sheet;
  sheet.bundles = std::move(bundles);
  sheet.deltas = std::move(deltas);
  return sheet;
}

TEST(SheetCoverageTest, CoversEachBundleInTheDirectionTheSheetMovesIt) {
  SheetCoverage coverage(5);
  coverage.Cover(Sheet({1, 3}, {2, -1}));
  EXPECT_THAT(Bundles(coverage.CoveringSheet(1, true)), Optional(ElementsAre(1, 3)));
  EXPECT_THAT(Bundles(coverage.CoveringSheet(3, false)), Optional(ElementsAre(1, 3)));
  EXPECT_EQ(coverage.CoveringSheet(1, false), std::nullopt);
  EXPECT_EQ(coverage.CoveringSheet(3, true), std::nullopt);
  EXPECT_EQ(coverage.CoveringSheet(0, true), std::nullopt);
}

TEST(SheetCoverageTest, TheLatestSheetAnswersAndClearForgetsAll) {
  SheetCoverage coverage(4);
  coverage.Cover(Sheet({0, 2}, {1, 1}));
  coverage.Cover(Sheet({2, 3}, {1, 1}));
  EXPECT_THAT(Bundles(coverage.CoveringSheet(0, true)), Optional(ElementsAre(0, 2)));
  EXPECT_THAT(Bundles(coverage.CoveringSheet(2, true)), Optional(ElementsAre(2, 3)));
  coverage.Clear();
  for (BundleId b = 0; b < 4; ++b) {
    EXPECT_EQ(coverage.CoveringSheet(b, true), std::nullopt);
    EXPECT_EQ(coverage.CoveringSheet(b, false), std::nullopt);
  }
  coverage.Cover(Sheet({3}, {-4}));
  EXPECT_THAT(Bundles(coverage.CoveringSheet(3, false)), Optional(ElementsAre(3)));
  EXPECT_EQ(coverage.CoveringSheet(2, true), std::nullopt);
}

// The id names the sheet, so that the roots it answers can share what they depend on
// (core/isp/greedy_queue.h): one id per sheet, never reused after Clear.
TEST(SheetCoverageTest, EachSheetHasItsOwnId) {
  SheetCoverage coverage(4);
  coverage.Cover(Sheet({0, 2}, {1, 1}));
  coverage.Cover(Sheet({1, 3}, {1, 1}));
  const uint64_t first = coverage.CoveringSheet(0, true)->id;
  EXPECT_EQ(coverage.CoveringSheet(2, true)->id, first);
  EXPECT_NE(coverage.CoveringSheet(1, true)->id, first);
  coverage.Clear();
  coverage.Cover(Sheet({0, 2}, {1, 1}));
  EXPECT_NE(coverage.CoveringSheet(0, true)->id, first);
}

}  // namespace
}  // namespace ispq
