// SPDX-License-Identifier: Apache-2.0
// The conversions between the quantization messages and the core types: each scaling kind and
// option reaches QuantizeOptions (and bad ones are refused with a message), every result field
// and statistic lands in the field of its name, optional values stay unset when absent, phases
// and terminations map one to one, and a result's q must have one entry per arc.
#include "core/proto/quantization_proto.h"

#include <cmath>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

// Two unit blocks side by side: 20 arcs of length 1, levels as the exporter writes them.
const TMesh& Mesh() {
  static const TMesh* const kMesh = [] {
    testing::GridTMeshSpec spec;
    spec.blocks = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
    absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(spec);
    return new TMesh(testing::TMeshOrDie(grid->proto()));
  }();
  return *kMesh;
}

v1::QuantizationOptions WithFactor(double factor) {
  v1::QuantizationOptions options;
  options.mutable_scaling()->set_factor(factor);
  return options;
}

TEST(QuantizationProtoTest, EachScalingKindBecomesItsChoice) {
  v1::Scaling scaling;
  EXPECT_EQ(ScalingChoiceFromProto(scaling).kind, ScalingChoice::Kind::kUnset);
  scaling.set_factor(2.5);
  EXPECT_EQ(ScalingChoiceFromProto(scaling).kind, ScalingChoice::Kind::kFactor);
  EXPECT_EQ(ScalingChoiceFromProto(scaling).factor, 2.5);
  scaling.set_level_percent(17);
  EXPECT_EQ(ScalingChoiceFromProto(scaling).kind, ScalingChoice::Kind::kLevelPercent);
  EXPECT_EQ(ScalingChoiceFromProto(scaling).percent, 17);
  scaling.set_target_hexes(int64_t{1} << 40);
  EXPECT_EQ(ScalingChoiceFromProto(scaling).kind, ScalingChoice::Kind::kTargetHexes);
  EXPECT_EQ(ScalingChoiceFromProto(scaling).target_hexes, int64_t{1} << 40);
}

TEST(QuantizationProtoTest, OptionsLeftUnsetKeepTheCoreDefaults) {
  const absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(WithFactor(3), Mesh());
  ASSERT_TRUE(options.ok()) << options.status();
  const QuantizeOptions defaults;
  EXPECT_EQ(options->scaling, 3);
  EXPECT_EQ(options->mixed_sign, defaults.mixed_sign);
  EXPECT_EQ(options->decompose, defaults.decompose);
  EXPECT_EQ(options->per_arc_nonnegative, false);
  EXPECT_EQ(options->separation, SeparationRule::kBothSearches);
  EXPECT_TRUE(std::isinf(options->time_limit_seconds));
  EXPECT_EQ(options->method, QuantizationMethod::kIsp);
  EXPECT_EQ(options->lower_bound, LowerBoundMode::kAuto);
}

TEST(QuantizationProtoTest, EverySetOptionReachesTheCore) {
  v1::QuantizationOptions proto = WithFactor(2);
  proto.set_mixed_sign(false);
  proto.set_decompose(false);
  proto.set_per_arc_nonnegative(true);
  proto.set_reference_block_boxes(true);
  proto.mutable_time_limit()->set_seconds(1);
  proto.mutable_time_limit()->set_nanos(500'000'000);
  proto.set_method(v1::METHOD_EXACT);
  proto.set_lower_bound(false);
  const absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(proto, Mesh());
  ASSERT_TRUE(options.ok()) << options.status();
  EXPECT_FALSE(options->mixed_sign);
  EXPECT_FALSE(options->decompose);
  EXPECT_TRUE(options->per_arc_nonnegative);
  EXPECT_EQ(options->separation, SeparationRule::kReferenceSearch);
  EXPECT_DOUBLE_EQ(options->time_limit_seconds, 1.5);
  EXPECT_EQ(options->method, QuantizationMethod::kExact);
  EXPECT_EQ(options->lower_bound, LowerBoundMode::kNever);
  proto.set_lower_bound(true);
  proto.set_method(v1::METHOD_ISP);
  EXPECT_EQ(QuantizeOptionsFromProto(proto, Mesh())->lower_bound, LowerBoundMode::kAlways);
  EXPECT_EQ(QuantizeOptionsFromProto(proto, Mesh())->method, QuantizationMethod::kIsp);
}

TEST(QuantizationProtoTest, ALevelIsResolvedAgainstTheMesh) {
  v1::QuantizationOptions proto;
  proto.mutable_scaling()->set_level_percent(100);
  const absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(proto, Mesh());
  ASSERT_TRUE(options.ok()) << options.status();
  EXPECT_EQ(options->scaling, *ResolveScaling(ScalingChoice::LevelPercent(100), Mesh()));
}

TEST(QuantizationProtoTest, BadOptionsAreRefusedWithAMessage) {
  const auto error = [](const v1::QuantizationOptions& proto) {
    const absl::StatusOr<QuantizeOptions> options = QuantizeOptionsFromProto(proto, Mesh());
    EXPECT_EQ(options.status().code(), absl::StatusCode::kInvalidArgument);
    return std::string(options.status().message());
  };
  EXPECT_FALSE(error(v1::QuantizationOptions()).empty());  // no scaling chosen
  EXPECT_FALSE(error(WithFactor(-1)).empty());
  v1::QuantizationOptions zero_time = WithFactor(1);
  zero_time.mutable_time_limit();  // set, but 0 s
  EXPECT_EQ(error(zero_time), "time limit 0s is not positive");
  v1::QuantizationOptions negative_time = WithFactor(1);
  negative_time.mutable_time_limit()->set_seconds(-2);
  EXPECT_EQ(error(negative_time), "time limit -2s is not positive");
  v1::QuantizationOptions unknown_method = WithFactor(1);
  unknown_method.set_method(static_cast<v1::Method>(42));
  EXPECT_EQ(error(unknown_method), "method 42 is not a known method");
  // Targets beyond the representable range (core/quantization_limits.h).
  EXPECT_THAT(error(WithFactor(1e12)), HasSubstr("above the limit"));
}

QuantizeResult SampleResult() {
  QuantizeResult result;
  result.termination = Termination::kTimeLimit;
  result.valid = true;
  result.q.assign(Mesh().num_arcs(), 3);
  result.q[0] = 0;
  result.objective = 12.5;
  result.hexes = 54;
  return result;
}

TEST(QuantizationProtoTest, AResultKeepsItsValuesAndLeavesAbsentBoundsUnset) {
  const v1::QuantizationResult proto = QuantizationResultToProto(SampleResult(), 2.0, Mesh());
  EXPECT_EQ(proto.q_size(), Mesh().num_arcs());
  EXPECT_EQ(proto.q(0), 0);
  EXPECT_EQ(proto.q(1), 3);
  EXPECT_EQ(proto.objective(), 12.5);
  EXPECT_EQ(proto.hexes(), 54);
  EXPECT_EQ(proto.scaling(), 2.0);
  EXPECT_TRUE(proto.valid());
  EXPECT_EQ(proto.termination(), v1::TIME_LIMIT);
  EXPECT_EQ(proto.mesh_name(), Mesh().name());
  EXPECT_FALSE(proto.has_lower_bound());
  EXPECT_FALSE(proto.has_gap());

  QuantizeResult bounded = SampleResult();
  bounded.lower_bound = 0.0;  // a bound of 0 is a bound, not "absent"
  bounded.gap = 1.0;
  const v1::QuantizationResult with_bound = QuantizationResultToProto(bounded, 2.0, Mesh());
  ASSERT_TRUE(with_bound.has_lower_bound());
  EXPECT_EQ(with_bound.lower_bound(), 0.0);
  EXPECT_EQ(with_bound.gap(), 1.0);
}

TEST(QuantizationProtoTest, SeparationRowsKeepTheirTermsInOrder) {
  QuantizeResult result = SampleResult();
  EXPECT_EQ(QuantizationResultToProto(result, 1.0, Mesh()).separation_rows_size(), 0);
  result.separation_rows = {{.terms = {{4, 1}, {0, 2}, {7, -1}}, .rhs = 1},
                            {.terms = {{3, 1}}, .rhs = 2}};
  const v1::QuantizationResult proto = QuantizationResultToProto(result, 1.0, Mesh());
  ASSERT_EQ(proto.separation_rows_size(), 2);
  EXPECT_THAT(proto.separation_rows(0).arcs(), ::testing::ElementsAre(4, 0, 7));
  EXPECT_THAT(proto.separation_rows(0).coefficients(), ::testing::ElementsAre(1, 2, -1));
  EXPECT_EQ(proto.separation_rows(0).rhs(), 1);
  EXPECT_THAT(proto.separation_rows(1).arcs(), ::testing::ElementsAre(3));
  EXPECT_THAT(proto.separation_rows(1).coefficients(), ::testing::ElementsAre(1));
  EXPECT_EQ(proto.separation_rows(1).rhs(), 2);
}

// The hex count only means something for a valid q; an invalid result reports 0.
TEST(QuantizationProtoTest, AnInvalidResultHasNoHexCount) {
  QuantizeResult invalid = SampleResult();
  invalid.valid = false;
  const v1::QuantizationResult proto = QuantizationResultToProto(invalid, 1.0, Mesh());
  EXPECT_FALSE(proto.valid());
  EXPECT_EQ(proto.hexes(), 0);
}

TEST(QuantizationProtoTest, TerminationsMapOneToOne) {
  const std::map<Termination, v1::Termination> expected = {
      {Termination::kConverged, v1::CONVERGED},
      {Termination::kTimeLimit, v1::TIME_LIMIT},
      {Termination::kInterrupted, v1::INTERRUPTED},
      {Termination::kOptimal, v1::OPTIMAL}};
  for (const auto& [core, proto] : expected) {
    QuantizeResult result = SampleResult();
    result.termination = core;
    EXPECT_EQ(QuantizationResultToProto(result, 1.0, Mesh()).termination(), proto)
        << TerminationName(core);
  }
}

TEST(QuantizationProtoTest, EveryStatisticLandsInTheFieldOfItsName) {
  QuantizeResult result = SampleResult();
  QuantizeStats& s = result.stats;
  const std::map<std::string, double> expected = {
      {"lp_solves", s.lp_solves = 1},
      {"lp_pivots", s.lp_pivots = 2},
      {"lp_degenerate_pivots", s.lp_degenerate_pivots = 3},
      {"lp_refactorizations", s.lp_refactorizations = 4},
      {"lp_fallback_solves", s.lp_fallback_solves = 5},
      {"lp_stalled_solves", s.lp_stalled_solves = 6},
      {"covered_checks", s.covered_checks = 7},
      {"sheets_inflating", s.sheets_inflating = 8},
      {"sheets_deflating", s.sheets_deflating = 9},
      {"sheets_mixed", s.sheets_mixed = 10},
      {"separating_updates", s.separating_updates = 11},
      {"failsafe_updates", s.failsafe_updates = 12},
      {"lcd_one", s.lcd_one = 13},
      {"lcd_two", s.lcd_two = 14},
      {"lcd_more", s.lcd_more = 15},
      {"separation_rounds", s.separation_rounds = 16},
      {"separation_rows", s.separation_rows = 17},
      {"subproblems", s.subproblems = 18},
      {"greedy_seconds", s.greedy_seconds = 19.5},
      {"separation_search_seconds", s.separation_search_seconds = 20.5},
      {"separating_update_seconds", s.separating_update_seconds = 21.5},
      {"lower_bound_seconds", s.lower_bound_seconds = 22.5},
      {"layers_seconds", s.layers_seconds = 23.5},
      {"milp_solves", s.milp_solves = 24},
      {"milp_nodes", s.milp_nodes = 25},
      {"milp_incumbents", s.milp_incumbents = 26},
      {"exact_seconds", s.exact_seconds = 27.5},
      {"solve_seconds", s.solve_seconds = 28.5},
      {"flow_solves", s.flow_solves = 29},
  };
  const v1::QuantizationStats stats = QuantizationResultToProto(result, 1.0, Mesh()).stats();
  const google::protobuf::Descriptor* descriptor = stats.GetDescriptor();
  const google::protobuf::Reflection* reflection = stats.GetReflection();
  ASSERT_EQ(descriptor->field_count(), static_cast<int>(expected.size()));
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const google::protobuf::FieldDescriptor* field = descriptor->field(i);
    ASSERT_TRUE(expected.contains(field->name())) << field->name();
    double value = 0;
    switch (field->cpp_type()) {
      case google::protobuf::FieldDescriptor::CPPTYPE_INT64:
        value = static_cast<double>(reflection->GetInt64(stats, field));
        break;
      case google::protobuf::FieldDescriptor::CPPTYPE_INT32:
        value = reflection->GetInt32(stats, field);
        break;
      case google::protobuf::FieldDescriptor::CPPTYPE_DOUBLE:
        value = reflection->GetDouble(stats, field);
        break;
      default:
        ADD_FAILURE() << field->name() << " has an unexpected type";
    }
    EXPECT_EQ(value, expected.at(field->name())) << field->name();
  }
}

TEST(QuantizationProtoTest, ProgressKeepsItsValuesAndPhasesMapOneToOne) {
  ProgressEvent event{.phase = QuantizationPhase::kSeparation,
                      .iteration = 7,
                      .separation_round = 2,
                      .objective = 3.25,
                      .violated_constraints = 4,
                      .separating = true,
                      .elapsed_seconds = 1.5,
                      .lp_solves = 11,
                      .q = {},
                      .lower_bound = std::nullopt};
  v1::Progress proto = ProgressToProto(event);
  EXPECT_EQ(proto.phase(), v1::SEPARATION);
  EXPECT_EQ(proto.iteration(), 7);
  EXPECT_EQ(proto.separation_round(), 2);
  EXPECT_EQ(proto.objective(), 3.25);
  EXPECT_EQ(proto.violated_constraints(), 4);
  EXPECT_TRUE(proto.separating());
  EXPECT_EQ(proto.elapsed_seconds(), 1.5);
  EXPECT_EQ(proto.lp_solves(), 11);
  EXPECT_FALSE(proto.has_lower_bound());
  event.lower_bound = 0.0;
  EXPECT_TRUE(ProgressToProto(event).has_lower_bound());

  const std::map<QuantizationPhase, v1::Phase> phases = {
      {QuantizationPhase::kGreedy, v1::GREEDY},
      {QuantizationPhase::kSeparation, v1::SEPARATION},
      {QuantizationPhase::kFailsafe, v1::FAILSAFE},
      {QuantizationPhase::kFinal, v1::FINAL},
      {QuantizationPhase::kExact, v1::EXACT},
      {QuantizationPhase::kLayers, v1::LAYERS}};
  for (const auto& [core, expected] : phases) {
    event.phase = core;
    EXPECT_EQ(ProgressToProto(event).phase(), expected) << QuantizationPhaseName(core);
  }
}

TEST(QuantizationProtoTest, AResultsQNeedsOneEntryPerArc) {
  v1::QuantizationResult result = QuantizationResultToProto(SampleResult(), 1.0, Mesh());
  const absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(result, Mesh());
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(*q, SampleResult().q);
  result.mutable_q()->RemoveLast();
  const absl::StatusOr<std::vector<int64_t>> short_q = QuantizationFromProto(result, Mesh());
  EXPECT_EQ(short_q.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(short_q.status().message(), "the result has " + std::to_string(Mesh().num_arcs() - 1) +
                                            " arc lengths but the mesh has " +
                                            std::to_string(Mesh().num_arcs()) + " arcs");
}

}  // namespace
}  // namespace ispq
