// SPDX-License-Identifier: Apache-2.0
#include "core/quantization_validator.h"

#include <algorithm>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/quantization_limits.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/consistent_quantizations.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::ConsistentQuantizations;
using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::RealTMeshPath;
using ::ispq::testing::ShortName;
using ::testing::HasSubstr;

// The cube with the given extents along u, v, w (every edge a single arc).
std::vector<int64_t> CubeQ(const TMesh& cube, int64_t u, int64_t v, int64_t w) {
  std::vector<int64_t> q(cube.num_arcs());
  const int64_t extent[3] = {u, v, w};
  for (int edge = 0; edge < kNumEdges; ++edge) {
    for (ArcId a : cube.block_edge_arcs(0, edge)) q[a] = extent[EdgeAxis(edge)];
  }
  return q;
}

// Two by two by two unit cubes around a feature node at (1, 1, 1).
absl::StatusOr<testing::GridTMesh> EightCubesAroundAFeatureNode() {
  testing::GridTMeshSpec spec;
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < 2; ++j) {
      for (int i = 0; i < 2; ++i) spec.blocks.push_back({{i, j, k}, {i + 1, j + 1, k + 1}});
    }
  }
  spec.feature_nodes = {{1, 1, 1}};
  return testing::BuildGridTMesh(spec);
}

// A consistent q with the bottom layer of cubes flat: the feature node touches the bottom.
std::vector<int64_t> FlatBottomQ(const testing::GridTMesh& grid, const TMesh& mesh) {
  std::vector<int64_t> q;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const auto& [from, to] = grid.arc_ends(a);
    q.push_back(from[2] == to[2] || from[2] == 1 ? 1 : 0);
  }
  return q;
}

int CountLines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

TEST(QuantizationValidatorTest, RejectsAWrongSize) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const absl::StatusOr<ValidationReport> report =
      ValidateQuantization(cube, std::vector<int64_t>(11, 1));
  EXPECT_EQ(report.status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(QuantizationValidatorTest, ValidCube) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(cube, CubeQ(cube, 1, 2, 3));
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_TRUE(report->valid());
  EXPECT_TRUE(report->separation_checked);
  EXPECT_EQ(report->Describe(), "");
}

// The last line of defence against overflow (issue 7): values a 32-bit q would wrap and hex
// counts beyond int64 are never certified, however consistent and separated they are.
TEST(QuantizationValidatorTest, RefusesValuesOutsideTheRepresentableRange) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const absl::StatusOr<ValidationReport> wrapped =
      ValidateQuantization(cube, CubeQ(cube, int64_t{1} << 31, 1, 1));
  ASSERT_TRUE(wrapped.ok());
  EXPECT_FALSE(wrapped->valid());
  EXPECT_EQ(wrapped->out_of_range.size(), 4u);  // the four u-edges
  EXPECT_THAT(wrapped->Describe(), HasSubstr("outside the representable range"));

  const absl::StatusOr<ValidationReport> negative =
      ValidateQuantization(cube, CubeQ(cube, 1, -(int64_t{1} << 40), 1));
  ASSERT_TRUE(negative.ok());
  EXPECT_EQ(negative->out_of_range.size(), 4u);
  EXPECT_FALSE(negative->valid());

  // In range arc by arc, but 2^90 hexes.
  const absl::StatusOr<ValidationReport> huge =
      ValidateQuantization(cube, CubeQ(cube, kMaxArcLength, kMaxArcLength, kMaxArcLength));
  ASSERT_TRUE(huge.ok());
  EXPECT_TRUE(huge->out_of_range.empty());
  EXPECT_TRUE(huge->consistent());
  EXPECT_TRUE(huge->hexes_overflow);
  EXPECT_FALSE(huge->valid());
  EXPECT_THAT(huge->Describe(), HasSubstr("hex count does not fit"));

  const absl::StatusOr<ValidationReport> large_but_fine =
      ValidateQuantization(cube, CubeQ(cube, kMaxArcLength, kMaxArcLength, 1));
  ASSERT_TRUE(large_but_fine.ok());
  EXPECT_TRUE(large_but_fine->valid()) << large_but_fine->Describe();
}

TEST(QuantizationValidatorTest, InconsistentCube) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  std::vector<int64_t> q = CubeQ(cube, 1, 1, 1);
  const ArcId a = cube.block_edge_arcs(0, EdgeCode(1, false, false))[0];  // a v-edge
  q[a] = 3;
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(cube, q);
  ASSERT_TRUE(report.ok());
  EXPECT_FALSE(report->consistent());
  EXPECT_FALSE(report->separation_checked);
  EXPECT_FALSE(report->valid());
  // The two faces containing the edge disagree along v by 2.
  ASSERT_EQ(report->consistency.size(), 2u);
  for (const ConsistencyViolation& c : report->consistency) {
    EXPECT_EQ(c.axis, 1);
    EXPECT_EQ(std::abs(c.difference), 2);
    const std::span<const HalfpatchId> around = cube.arc_halfpatches(a);
    EXPECT_TRUE(std::any_of(around.begin(), around.end(),
                            [&](HalfpatchId hp) { return PatchOf(hp) == c.patch; }));
  }
  const std::string text = report->Describe();
  EXPECT_EQ(CountLines(text), 2);
  EXPECT_THAT(text, HasSubstr(absl::StrCat("patch ", report->consistency[0].patch,
                                           " axis v: sides differ by ")));
}

TEST(QuantizationValidatorTest, CollapsedAndNegativeCube) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  {
    const absl::StatusOr<ValidationReport> report =
        ValidateQuantization(cube, CubeQ(cube, 0, 1, 1));
    ASSERT_TRUE(report.ok());
    EXPECT_TRUE(report->consistent());
    EXPECT_FALSE(report->separation_checked);
    ASSERT_EQ(report->simple.size(), 4u);  // the four u-edge links
    for (size_t i = 0; i < report->simple.size(); ++i) {
      EXPECT_EQ(report->simple[i].kind, SimpleRowKind::kLink);
      EXPECT_EQ(report->simple_values[i], 0);
    }
    EXPECT_THAT(
        report->Describe(),
        HasSubstr(absl::StrCat("link (entity ", report->simple[0].element, ") has length 0")));
  }
  {
    ValidationOptions options;
    options.per_arc_lower_bound = 0;
    const absl::StatusOr<ValidationReport> report =
        ValidateQuantization(cube, CubeQ(cube, 1, -1, 1), options);
    ASSERT_TRUE(report.ok());
    EXPECT_TRUE(report->consistent());
    // 4 arc bounds, 4 links, the 4 faces along v (their arcs sum to 0) and the block's v extent.
    const std::string text = report->Describe(100);
    EXPECT_THAT(text, HasSubstr("block 0 has negative extent -1 along v"));
    EXPECT_THAT(text, HasSubstr("below the lower bound 0"));
    int blocks = 0, bounds = 0;
    for (const SimpleRow& r : report->simple) {
      blocks += r.kind == SimpleRowKind::kBlockExtent;
      bounds += r.kind == SimpleRowKind::kArcLowerBound;
    }
    EXPECT_EQ(blocks, 1);
    EXPECT_EQ(bounds, 4);
    EXPECT_EQ(CountLines(text), static_cast<int>(report->simple.size()));
    // At most max_lines lines, the last one counting the rest.
    const std::string short_text = report->Describe(3);
    EXPECT_EQ(CountLines(short_text), 3);
    EXPECT_THAT(short_text,
                HasSubstr(absl::StrCat("... and ", report->simple.size() - 2, " more problems")));
  }
}

// T6's feature node on the bottom boundary: consistent, simple rows hold, one violation.
TEST(QuantizationValidatorTest, SeparationViolation) {
  const absl::StatusOr<testing::GridTMesh> grid = EightCubesAroundAFeatureNode();
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = testing::TMeshOrDie(grid->proto());
  const std::vector<int64_t> q = FlatBottomQ(*grid, mesh);
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, q);
  ASSERT_TRUE(report.ok());
  EXPECT_TRUE(report->consistent());
  EXPECT_TRUE(report->simple.empty());
  EXPECT_TRUE(report->separation_checked);
  // The same violation, found by each of the two searches the product requires.
  ASSERT_EQ(report->separation.size(), 2u);
  EXPECT_FALSE(report->valid());
  EXPECT_EQ(report->separation[0].found_by, BlockBoxMode::kReferenceUnsorted);
  EXPECT_EQ(report->separation[1].found_by, BlockBoxMode::kSorted);
  for (const SeparationViolation& v : report->separation) {
    EXPECT_EQ(v.start_node, grid->NodeAt({1, 1, 1}));
    EXPECT_EQ(v.default_row, report->separation[0].default_row);
  }
  const SeparationViolation& v = report->separation[0];
  EXPECT_EQ(report->Describe(),
            absl::StrCat("critical node ", v.start_node, " touches patch ", v.target,
                         " (path 1 halfarcs, reference search)\n", "critical node ", v.start_node,
                         " touches patch ", v.target, " (path 1 halfarcs, sorted search)\n"));
}

// The caller's check (core/quantizer.cc hands its validator the run's): its verdicts on a q are
// the validator's own, whatever it was used for before.
TEST(QuantizationValidatorTest, WithTheCallersCheckReportsAsWithItsOwn) {
  const absl::StatusOr<testing::GridTMesh> grid = EightCubesAroundAFeatureNode();
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = testing::TMeshOrDie(grid->proto());
  std::vector<int64_t> flat_bottom = FlatBottomQ(*grid, mesh);
  std::vector<int64_t> ones(mesh.num_arcs(), 1);
  SeparationCheck check(mesh, SeparationRule::kBothSearches);
  for (const std::vector<int64_t>* q : {&ones, &flat_bottom, &ones, &flat_bottom}) {
    const absl::StatusOr<ValidationReport> own = ValidateQuantization(mesh, *q);
    const absl::StatusOr<ValidationReport> shared = ValidateQuantization(mesh, *q, {}, check);
    ASSERT_TRUE(own.ok() && shared.ok());
    EXPECT_EQ(shared->valid(), q == &ones);
    EXPECT_EQ(shared->separation.size(), q == &ones ? 0u : 2u);
    EXPECT_EQ(shared->Describe(), own->Describe());
  }
}

// A check answers FindAllViolations without searching for the last q its FindFirstViolations found
// clean (core/separation_check.h): on every shared mesh, for consistent q near the targets at
// several scales (the small ones with zero arcs and violations) and for the q before, its answers
// are a fresh check's.
TEST(QuantizationValidatorTest, ACheckRemembersOnlyWhatItsSearchesFound) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  int clean = 0, violated = 0;
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    const ConsistentQuantizations quantizations(mesh);
    SeparationCheck check(mesh, SeparationRule::kBothSearches);
    std::vector<int64_t> previous;
    for (double scale : {0.1, 0.3, 1.0, 3.0}) {
      const std::vector<int64_t> q = quantizations.NearTargets(scale);
      const bool passed = check.FindFirstViolations(q).empty();
      (passed ? clean : violated) += 1;
      SeparationCheck fresh(mesh, SeparationRule::kBothSearches);
      EXPECT_EQ(check.FindAllViolations(q).size(), fresh.FindAllViolations(q).size());
      EXPECT_EQ(fresh.FindAllViolations(q).empty(), passed);
      if (!previous.empty()) {
        EXPECT_EQ(check.FindAllViolations(previous).size(),
                  fresh.FindAllViolations(previous).size());
      }
      previous = q;
    }
  }
  // Both kinds of q occur (153 clean, 95 with violations), so both paths were taken.
  EXPECT_GT(clean, 0);
  EXPECT_GT(violated, 0);
}

TEST(QuantizationValidatorTest, RefusesACheckOfAnotherMeshOrRule) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const TMesh copy = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  const std::vector<int64_t> q = CubeQ(cube, 1, 2, 3);
  SeparationCheck of_copy(copy, SeparationRule::kBothSearches);
  EXPECT_EQ(ValidateQuantization(cube, q, {}, of_copy).status().code(),
            absl::StatusCode::kInvalidArgument);
  SeparationCheck reference_only(cube, SeparationRule::kReferenceSearch);
  EXPECT_EQ(ValidateQuantization(cube, q, {}, reference_only).status().code(),
            absl::StatusCode::kInvalidArgument);
  ValidationOptions reference_rule;
  reference_rule.separation = SeparationRule::kReferenceSearch;
  const absl::StatusOr<ValidationReport> report =
      ValidateQuantization(cube, q, reference_rule, reference_only);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_TRUE(report->valid());
}

// On every real mesh: q = 0 collapses every link and region (the search is not run); a
// consistent q with every arc positive passes consistency and the simple rows, and every
// separation violation reported for it is violated by it.
TEST(QuantizationValidatorTest, RealMeshes) {
  const std::vector<std::string> files = RealTMeshFiles();
  ASSERT_FALSE(files.empty());
  for (const std::string& file : files) {
    SCOPED_TRACE(ShortName(file));
    const TMesh mesh = LoadTMeshOrDie(file);
    int links_and_regions = 0;
    for (EntityId e = 0; e < mesh.num_entities(); ++e) {
      links_and_regions += mesh.entity_dim(e) != EntityDim::kNode;
    }
    const absl::StatusOr<ValidationReport> zero =
        ValidateQuantization(mesh, std::vector<int64_t>(mesh.num_arcs(), 0));
    ASSERT_TRUE(zero.ok());
    EXPECT_TRUE(zero->consistent());
    EXPECT_EQ(static_cast<int>(zero->simple.size()), links_and_regions);
    EXPECT_FALSE(zero->separation_checked);
    EXPECT_EQ(CountLines(zero->Describe(5)), 5);

    const ConsistentQuantizations quantizations(mesh);
    std::vector<int64_t> q;
    for (double scale = 1.0;; scale *= 2) {
      q = quantizations.NearTargets(scale);
      if (*std::min_element(q.begin(), q.end()) >= 1) break;
    }
    const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, q);
    ASSERT_TRUE(report.ok());
    EXPECT_TRUE(report->consistent());
    EXPECT_TRUE(report->simple.empty());
    EXPECT_TRUE(report->separation_checked);
    for (const SeparationViolation& v : report->separation) {
      EXPECT_FALSE(v.default_row.IsSatisfiedBy(q));
      EXPECT_FALSE(v.failsafe_row.IsSatisfiedBy(q));
    }
    EXPECT_EQ(report->valid(), report->separation.empty());
  }
}

}  // namespace
}  // namespace ispq
