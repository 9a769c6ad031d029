// SPDX-License-Identifier: Apache-2.0
// Quantize() on the real T-meshes: every result at every level is checked by the
// validator, plus the contract around options, observers, interruption and time limits.
#include "core/quantizer.h"

#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "core/arc_bundles.h"
#include "core/block_extents.h"
#include "core/consistency_matrix.h"
#include "core/exact/cbc_milp_solver.h"
#include "core/exact/lower_bound.h"
#include "core/quantization_limits.h"
#include "core/quantization_validator.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::ispq::testing::LoadTMeshOrDie;
using ::ispq::testing::RealTMeshFiles;
using ::ispq::testing::RealTMeshPath;
using ::ispq::testing::ShortName;
using ::testing::HasSubstr;

double Objective(const TMesh& mesh, double scaling, const std::vector<int64_t>& q) {
  double sum = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    sum += std::pow(static_cast<double>(q[a]) - scaling * mesh.arc_length(a), 2);
  }
  return sum;
}

// The result's separation rows hold for its q and name each bundle by its smallest arc, once.
void ExpectSeparationRowsOverBundles(const TMesh& mesh, const QuantizeResult& result,
                                     const std::string& context) {
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  for (const SeparationRow& row : result.separation_rows) {
    EXPECT_TRUE(row.IsSatisfiedBy(result.q)) << context;
    EXPECT_FALSE(row.terms.empty()) << context;
    std::vector<BundleId> seen;
    for (const LinearTerm& term : row.terms) {
      ASSERT_GE(term.var, 0) << context;
      ASSERT_LT(term.var, mesh.num_arcs()) << context;
      EXPECT_NE(term.coef, 0) << context;
      const BundleId b = bundles.bundle_of(term.var);
      EXPECT_EQ(bundles.arcs(b)[0], term.var) << context << ": not its bundle's smallest arc";
      EXPECT_THAT(seen, ::testing::Not(::testing::Contains(b))) << context;
      seen.push_back(b);
    }
  }
}

// Checks a converged result against the validator and recomputes what it reports.
void ExpectValidResult(const TMesh& mesh, const QuantizeOptions& options,
                       const QuantizeResult& result, const std::string& context) {
  EXPECT_EQ(result.termination, Termination::kConverged) << context;
  EXPECT_TRUE(result.valid) << context;
  ASSERT_EQ(result.q.size(), static_cast<size_t>(mesh.num_arcs())) << context;
  ValidationOptions validation;
  validation.separation = options.separation;
  if (options.per_arc_nonnegative) validation.per_arc_lower_bound = 0;
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, result.q, validation);
  ASSERT_TRUE(report.ok()) << context << ": " << report.status();
  EXPECT_TRUE(report->valid()) << context << ":\n" << report->Describe();
  EXPECT_NEAR(result.objective, Objective(mesh, options.scaling, result.q),
              1e-9 * (1 + result.objective))
      << context;
  EXPECT_EQ(result.hexes, HexCount(mesh, result.q).value_or(-1)) << context;
  EXPECT_GT(result.stats.lp_solves, 0) << context;
  ExpectSeparationRowsOverBundles(mesh, result, context);
  EXPECT_EQ(result.stats.lcd_one + result.stats.lcd_two + result.stats.lcd_more > 0,
            result.stats.lp_solves > 0)
      << context;
}

TEST(QuantizerTest, RealDataIsPresent) { EXPECT_FALSE(RealTMeshFiles().empty()); }

// Every real mesh at all eight levels (the whole set takes seconds in Release).
class QuantizerRealMeshTest : public ::testing::TestWithParam<std::string> {};

TEST_P(QuantizerRealMeshTest, EveryLevelGivesAValidResult) {
  const TMesh mesh = LoadTMeshOrDie(GetParam());
  ASSERT_EQ(mesh.levels().size(), 8u);
  for (const Level& level : mesh.levels()) {
    QuantizeOptions options;
    options.scaling = level.scaling;
    const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
    const std::string context =
        ShortName(GetParam()) + " at " + std::to_string(level.percent) + "%";
    ASSERT_TRUE(result.ok()) << context << ": " << result.status();
    ExpectValidResult(mesh, options, *result, context);
  }
}

INSTANTIATE_TEST_SUITE_P(RealMeshes, QuantizerRealMeshTest, ::testing::ValuesIn(RealTMeshFiles()),
                         [](const auto& info) {
                           std::string name = ShortName(info.param);
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

// The single cube: every arc becomes 1 at every level (the reference's objective is 3).
TEST(QuantizerTest, CubeGetsOneOnEveryArc) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  for (const Level& level : cube.levels()) {
    QuantizeOptions options;
    options.scaling = level.scaling;
    const absl::StatusOr<QuantizeResult> result = Quantize(cube, options);
    ASSERT_TRUE(result.ok()) << result.status();
    EXPECT_EQ(result->q, std::vector<int64_t>(12, 1)) << level.percent;
    EXPECT_EQ(result->hexes, 1);
    EXPECT_NEAR(result->objective, 3.0, 0.01) << level.percent;
    ExpectValidResult(cube, options, *result, "cube");
  }
}

// The rows a result carries are the rows its bound is proven for: the bound computed again from
// them is the result's, and without them it is never higher.
TEST(QuantizerTest, ResultCarriesTheSeparationRowsItsBoundIsProvenFor) {
  int with_rows = 0, raised = 0;
  for (const std::string& path : RealTMeshFiles()) {
    const TMesh mesh = LoadTMeshOrDie(path);
    for (const Level& level : mesh.levels()) {
      if (level.percent != 100 && level.percent != 10) continue;
      QuantizeOptions options;
      options.scaling = level.scaling;
      options.lower_bound = LowerBoundMode::kAlways;
      const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
      const std::string context = ShortName(path) + " at " + std::to_string(level.percent) + "%";
      ASSERT_TRUE(result.ok()) << context << ": " << result.status();
      ASSERT_TRUE(result->lower_bound.has_value()) << context;
      ExpectSeparationRowsOverBundles(mesh, *result, context);
      if (result->separation_rows.empty()) continue;
      ++with_rows;
      const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
      const absl::StatusOr<double> again =
          ComputeLowerBound(mesh, options, result->q, result->separation_rows, *solver);
      ASSERT_TRUE(again.ok()) << context << ": " << again.status();
      EXPECT_NEAR(*again, *result->lower_bound, 1e-9 * (1 + *result->lower_bound)) << context;
      const absl::StatusOr<double> without =
          ComputeLowerBound(mesh, options, result->q, {}, *solver);
      ASSERT_TRUE(without.ok()) << context << ": " << without.status();
      EXPECT_LE(*without, *again + 1e-9 * (1 + *again)) << context;
      if (*without < *again - 1e-6 * (1 + *again)) ++raised;
    }
  }
  // The set has meshes whose features need rows beyond the simple ones at these levels, and on
  // some of them the rows are what lifts the bound.
  EXPECT_GE(with_rows, 10);
  EXPECT_GE(raised, 1);
  std::cout << with_rows << " results with rows, " << raised << " bounds raised by them\n";
}

TEST(QuantizerTest, ExactModeCarriesTheRowsOfItsLastMilp) {
  const TMesh mesh = LoadTMeshOrDie(RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels().back().scaling;
  options.method = QuantizationMethod::kExact;
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->termination, Termination::kOptimal);
  ExpectSeparationRowsOverBundles(mesh, *result, "notch, exact");
  EXPECT_FALSE(result->separation_rows.empty());
}

const std::vector<std::string>& SwitchMeshes() {
  static const auto* const kMeshes = new std::vector<std::string>{
      RealTMeshPath("hex-me/s04u_tetrahedron.tmesh.json"),
      RealTMeshPath("hex-me/s07c_notch.tmesh.json"),
      RealTMeshPath("singularity-constrained-fields/fanpart.tmesh.json")};
  return *kMeshes;
}

TEST(QuantizerTest, UniformSignSheetsGiveValidResultsWithoutMixedSheets) {
  for (const std::string& path : SwitchMeshes()) {
    const TMesh mesh = LoadTMeshOrDie(path);
    for (const Level& level : mesh.levels()) {
      QuantizeOptions options;
      options.scaling = level.scaling;
      options.mixed_sign = false;
      const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
      ASSERT_TRUE(result.ok()) << result.status();
      ExpectValidResult(mesh, options, *result, ShortName(path));
      EXPECT_EQ(result->stats.sheets_mixed, 0);
    }
  }
}

TEST(QuantizerTest, MixedSignSheetsAreUsedAndLowerTheTotalObjective) {
  int64_t mixed = 0;
  double with = 0, without = 0;
  const std::vector<std::string> files = RealTMeshFiles();
  for (size_t i = 0; i < files.size(); i += 3) {  // a third of the set is plenty
    const TMesh mesh = LoadTMeshOrDie(files[i]);
    const Level& level = mesh.levels()[3];
    QuantizeOptions options;
    options.scaling = level.scaling;
    const absl::StatusOr<QuantizeResult> on = Quantize(mesh, options);
    options.mixed_sign = false;
    const absl::StatusOr<QuantizeResult> off = Quantize(mesh, options);
    ASSERT_TRUE(on.ok() && off.ok());
    mixed += on->stats.sheets_mixed;
    with += on->objective;
    without += off->objective;
  }
  EXPECT_GT(mixed, 0);
  EXPECT_LT(with, without);  // paper section 5.1: mixed-sign sheets escape local minima
}

TEST(QuantizerTest, WithoutDecompositionOneSubproblemGivesValidResults) {
  for (const std::string& path : SwitchMeshes()) {
    const TMesh mesh = LoadTMeshOrDie(path);
    for (const Level& level : mesh.levels()) {
      QuantizeOptions options;
      options.scaling = level.scaling;
      options.decompose = false;
      const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
      ASSERT_TRUE(result.ok()) << result.status();
      ExpectValidResult(mesh, options, *result, ShortName(path));
      EXPECT_EQ(result->stats.subproblems, 1);
    }
  }
}

TEST(QuantizerTest, DecompositionSplitsIntoSeveralSubproblems) {
  // The real set has meshes whose sheet LP falls apart into independent pieces (section 4.4).
  int32_t most = 0;
  for (const std::string& path : RealTMeshFiles()) {
    const TMesh mesh = LoadTMeshOrDie(path);
    QuantizeOptions options;
    options.scaling = mesh.levels()[0].scaling;
    const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
    ASSERT_TRUE(result.ok());
    most = std::max(most, result->stats.subproblems);
    if (most > 1) break;
  }
  EXPECT_GT(most, 1);
}

TEST(QuantizerTest, PerArcNonNegativityKeepsEveryArcNonNegative) {
  for (const std::string& path : SwitchMeshes()) {
    const TMesh mesh = LoadTMeshOrDie(path);
    for (const Level& level : mesh.levels()) {
      QuantizeOptions options;
      options.scaling = level.scaling;
      options.per_arc_nonnegative = true;
      const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
      ASSERT_TRUE(result.ok()) << result.status();
      ExpectValidResult(mesh, options, *result, ShortName(path));
      for (int64_t x : result->q) EXPECT_GE(x, 0);
    }
  }
}

TEST(QuantizerTest, ReferenceSearchModeGivesResultsValidInThatMode) {
  const TMesh mesh = LoadTMeshOrDie(RealTMeshPath("hex-me/s04u_tetrahedron.tmesh.json"));
  for (const Level& level : mesh.levels()) {
    QuantizeOptions options;
    options.scaling = level.scaling;
    options.separation = SeparationRule::kReferenceSearch;
    const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
    ASSERT_TRUE(result.ok()) << result.status();
    ExpectValidResult(mesh, options, *result, "reference mode");
  }
}

TEST(QuantizerTest, IsDeterministic) {
  const TMesh mesh =
      LoadTMeshOrDie(RealTMeshPath("singularity-constrained-fields/fanpart.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[5].scaling;
  const absl::StatusOr<QuantizeResult> first = Quantize(mesh, options);
  const absl::StatusOr<QuantizeResult> second = Quantize(mesh, options);
  ASSERT_TRUE(first.ok() && second.ok());
  EXPECT_EQ(first->q, second->q);
  EXPECT_EQ(first->stats.lp_solves, second->stats.lp_solves);
}

TEST(QuantizerTest, RejectsBadOptions) {
  const TMesh cube = LoadTMeshOrDie(RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  for (double scaling : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(),
                         std::numeric_limits<double>::infinity()}) {
    QuantizeOptions options;
    options.scaling = scaling;
    EXPECT_EQ(Quantize(cube, options).status().code(), absl::StatusCode::kInvalidArgument)
        << scaling;
  }
  for (double limit : {-1.0, std::numeric_limits<double>::quiet_NaN()}) {
    QuantizeOptions options;
    options.time_limit_seconds = limit;
    EXPECT_EQ(Quantize(cube, options).status().code(), absl::StatusCode::kInvalidArgument) << limit;
  }
}

// Targets beyond the representable range are refused up front, naming the limit (issue 7): at
// s = 1e9 the notch's q used to wrap around int32 and be certified valid, and at 1e20 CLP aborted
// the process on an objective coefficient above 1e25.
TEST(QuantizerTest, RefusesTargetsOutsideTheRepresentableRange) {
  const TMesh notch = LoadTMeshOrDie(RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  for (double scaling : {1e9, 1e12, 1e20, 1e300}) {
    QuantizeOptions options;
    options.scaling = scaling;
    const absl::StatusOr<QuantizeResult> result = Quantize(notch, options);
    EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument) << scaling;
    EXPECT_THAT(std::string(result.status().message()), HasSubstr("above the limit")) << scaling;
  }
  // Just inside the limit on the longest arc, the result is valid and within the range.
  double longest = 0;
  for (ArcId a = 0; a < notch.num_arcs(); ++a) longest = std::max(longest, notch.arc_length(a));
  QuantizeOptions options;
  options.scaling = std::cbrt(0.5 * kMaxTargetHexes / ContinuousHexVolume(notch));
  options.scaling = std::min(options.scaling, 0.5 * kMaxTargetLength / longest);
  const absl::StatusOr<QuantizeResult> result = Quantize(notch, options);
  ASSERT_TRUE(result.ok()) << result.status();
  ExpectValidResult(notch, options, *result, "largest scaling");
  for (int64_t x : result->q) EXPECT_LE(std::abs(x), kMaxArcLength);
}

// A valid mesh whose arcs span 30 orders of magnitude: level 0 puts the shortest arc at 1/2 and
// the longest at 5e29, which is refused; levels that keep the targets in range still solve.
TEST(QuantizerTest, ExtremeLengthSpreadIsRefusedAtLevelZero) {
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
  spec.spacing[0] = {1e-30, 1.0};
  const absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(spec);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const TMesh mesh = testing::TMeshOrDie(grid->proto());
  QuantizeOptions options;
  options.scaling = mesh.levels()[0].scaling;
  const absl::StatusOr<QuantizeResult> refused = Quantize(mesh, options);
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(refused.status().message()), HasSubstr("above the limit"));
  options.scaling = mesh.levels().back().scaling;
  const absl::StatusOr<QuantizeResult> solved = Quantize(mesh, options);
  ASSERT_TRUE(solved.ok()) << solved.status();
  ExpectValidResult(mesh, options, *solved, "level 100");
}

// Records events; optionally interrupts once a condition holds.
class RecordingObserver : public ProgressObserver {
 public:
  RecordingObserver(SolveInterrupter* interrupter, bool wants_q, bool interrupt_when_separating)
      : interrupter_(interrupter),
        wants_q_(wants_q),
        interrupt_when_separating_(interrupt_when_separating) {}

  void OnProgress(const ProgressEvent& event) override {
    events_.push_back(event);
    q_sizes_.push_back(event.q.size());
    if (interrupter_ != nullptr && (!interrupt_when_separating_ || event.separating)) {
      interrupter_->Interrupt();
    }
  }
  bool WantsQuantization() const override { return wants_q_; }

  const std::vector<ProgressEvent>& events() const { return events_; }
  const std::vector<size_t>& q_sizes() const { return q_sizes_; }

 private:
  SolveInterrupter* interrupter_;
  bool wants_q_;
  bool interrupt_when_separating_;
  std::vector<ProgressEvent> events_;
  std::vector<size_t> q_sizes_;
};

TEST(QuantizerTest, ObserverSeesAMonotoneRunAndQOnlyOnRequest) {
  const TMesh mesh = LoadTMeshOrDie(RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[4].scaling;
  for (const bool wants_q : {false, true}) {
    RecordingObserver observer(nullptr, wants_q, false);
    const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options, &observer);
    ASSERT_TRUE(result.ok());
    ASSERT_FALSE(observer.events().empty());
    bool saw_separation_round = false, saw_separating = false;
    for (size_t i = 0; i < observer.events().size(); ++i) {
      const ProgressEvent& e = observer.events()[i];
      EXPECT_EQ(observer.q_sizes()[i], wants_q ? static_cast<size_t>(mesh.num_arcs()) : 0u);
      if (i > 0) {
        EXPECT_GE(e.iteration, observer.events()[i - 1].iteration);
        EXPECT_GE(e.separation_round, observer.events()[i - 1].separation_round);
        EXPECT_GE(e.elapsed_seconds, observer.events()[i - 1].elapsed_seconds);
      }
      if (e.separating) {
        EXPECT_EQ(e.violated_constraints, 0);
      }
      saw_separation_round |= e.phase == QuantizationPhase::kSeparation;
      saw_separating |= e.separating;
    }
    EXPECT_TRUE(saw_separation_round);
    EXPECT_TRUE(saw_separating);
    EXPECT_EQ(observer.events().back().iteration, result->stats.sheets_inflating +
                                                      result->stats.sheets_deflating +
                                                      result->stats.sheets_mixed);
  }
}

TEST(QuantizerTest, InterruptAtTheFirstEventStopsBeforeAnyValidQ) {
  const TMesh mesh =
      LoadTMeshOrDie(RealTMeshPath("singularity-constrained-fields/fanpart.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[2].scaling;
  SolveInterrupter interrupter;
  RecordingObserver observer(&interrupter, false, /*interrupt_when_separating=*/false);
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options, &observer, &interrupter);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->termination, Termination::kInterrupted);
  EXPECT_EQ(observer.events().size(), 1u);
  ASSERT_EQ(result->q.size(), static_cast<size_t>(mesh.num_arcs()));
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, result->q);
  ASSERT_TRUE(report.ok());
  EXPECT_EQ(result->valid, report->valid());
}

TEST(QuantizerTest, InterruptOnceSeparatingReturnsThatValidQ) {
  const TMesh mesh =
      LoadTMeshOrDie(RealTMeshPath("singularity-constrained-fields/fanpart.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[2].scaling;
  SolveInterrupter interrupter;
  RecordingObserver observer(&interrupter, true, /*interrupt_when_separating=*/true);
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options, &observer, &interrupter);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->termination, Termination::kInterrupted);
  EXPECT_TRUE(result->valid);
  const ProgressEvent& last = observer.events().back();
  EXPECT_TRUE(last.separating);
  EXPECT_NEAR(result->objective, last.objective, 1e-6 * (1 + last.objective));
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, result->q);
  ASSERT_TRUE(report.ok());
  EXPECT_TRUE(report->valid()) << report->Describe();
}

TEST(QuantizerTest, InterruptedBeforeTheStartReturnsTheInvalidStart) {
  const TMesh mesh = LoadTMeshOrDie(RealTMeshPath("hex-me/s02c_prism.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[0].scaling;
  SolveInterrupter interrupter;
  interrupter.Interrupt();
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options, nullptr, &interrupter);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->termination, Termination::kInterrupted);
  EXPECT_FALSE(result->valid);
  EXPECT_EQ(result->q, std::vector<int64_t>(mesh.num_arcs(), 0));
  EXPECT_EQ(result->stats.lp_solves, 0);
}

TEST(QuantizerTest, ZeroTimeLimitStopsAtOnce) {
  const TMesh mesh = LoadTMeshOrDie(RealTMeshPath("hex-me/s02c_prism.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[0].scaling;
  options.time_limit_seconds = 0;
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->termination, Termination::kTimeLimit);
  EXPECT_FALSE(result->valid);
}

TEST(QuantizerTest, GenerousTimeLimitConverges) {
  const TMesh mesh = LoadTMeshOrDie(RealTMeshPath("hex-me/s02c_prism.tmesh.json"));
  QuantizeOptions options;
  options.scaling = mesh.levels()[0].scaling;
  options.time_limit_seconds = 3600;
  const absl::StatusOr<QuantizeResult> result = Quantize(mesh, options);
  ASSERT_TRUE(result.ok()) << result.status();
  ExpectValidResult(mesh, options, *result, "prism");
}

TEST(QuantizerTest, NamesAreStable) {
  EXPECT_STREQ(TerminationName(Termination::kConverged), "converged");
  EXPECT_STREQ(TerminationName(Termination::kTimeLimit), "time_limit");
  EXPECT_STREQ(TerminationName(Termination::kInterrupted), "interrupted");
  EXPECT_STREQ(QuantizationPhaseName(QuantizationPhase::kGreedy), "greedy");
  EXPECT_STREQ(QuantizationPhaseName(QuantizationPhase::kSeparation), "separation");
  EXPECT_STREQ(QuantizationPhaseName(QuantizationPhase::kFailsafe), "failsafe");
  EXPECT_STREQ(QuantizationPhaseName(QuantizationPhase::kFinal), "final");
  EXPECT_STREQ(QuantizationPhaseName(QuantizationPhase::kLayers), "layers");
}

}  // namespace
}  // namespace ispq
