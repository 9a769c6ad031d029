// SPDX-License-Identifier: Apache-2.0
// Exact mode end to end (Quantize with QuantizationMethod::kExact, core/exact/exact_quantizer.h):
// proven optima on five small real meshes and on grid meshes with brute-force optima, never worse
// than ISP, improvements streamed as they are found, interruption, and the loop's variants. Every
// result is checked by the validator.
#include "core/exact/exact_quantizer.h"

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/exact/cbc_milp_solver.h"
#include "core/isp/clp_sheet_lp.h"
#include "core/isp/integer_sheet_pump.h"
#include "core/isp/isp_tuning.h"
#include "core/proto/quantization_proto.h"
#include "core/quantization_objective.h"
#include "core/quantization_validator.h"
#include "core/quantizer.h"
#include "gtest/gtest.h"
#include "tests/support/enumerated_optimum.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"
#include "tests/support/worked_examples.h"

namespace ispq {
namespace {

TMesh RealMesh(const std::string& model) {
  for (const std::string& file : testing::RealTMeshFiles()) {
    if (testing::ShortName(file).ends_with("/" + model)) return testing::LoadTMeshOrDie(file);
  }
  ADD_FAILURE() << "no real mesh " << model;
  return testing::TMeshOrDie(v1::TMesh());
}

void ExpectValid(const TMesh& mesh, const std::vector<int64_t>& q) {
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, q);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_TRUE(report->valid()) << report->Describe();
}

// Records exact mode's events; optionally interrupts at the first one.
class ExactEvents : public ProgressObserver {
 public:
  explicit ExactEvents(SolveInterrupter* interrupt_at_first = nullptr)
      : interrupter_(interrupt_at_first) {}
  void OnProgress(const ProgressEvent& event) override {
    if (event.phase != QuantizationPhase::kExact) return;
    if (interrupter_ != nullptr) interrupter_->Interrupt();
    events.push_back(event);
    if (!event.q.empty())
      improvements.push_back({event.objective, {event.q.begin(), event.q.end()}});
  }
  bool WantsQuantization() const override { return true; }

  std::vector<ProgressEvent> events;  // q not kept
  std::vector<testing::EnumeratedOptimum> improvements;

 private:
  SolveInterrupter* interrupter_;
};

// A valid start that is not optimal: ISP enforcing all rows of a search at once (the engine's
// behaviour before it took them two at a time). On s11c_cube_cyl at level 100 today's ISP is
// optimal, this start is not, and exact mode improves on it.
struct Start {
  std::vector<int64_t> q;
  double objective = 0;
};
Start AllRowsAtOnceIsp(const TMesh& mesh, double scaling) {
  QuantizeOptions options;
  options.scaling = scaling;
  IspTuning tuning;
  tuning.max_new_rows_per_search = std::numeric_limits<int>::max();
  absl::StatusOr<IspOutcome> outcome =
      RunIntegerSheetPump(mesh, options, ClpSheetLpFactory(), tuning, nullptr, nullptr);
  EXPECT_TRUE(outcome.ok() && outcome->separating);
  if (!outcome.ok()) return {};
  const double objective = QuantizationObjective(mesh, outcome->q, scaling);
  return {std::move(outcome->q), objective};
}

QuantizeOptions Exact(double scaling) {
  QuantizeOptions options;
  options.scaling = scaling;
  options.method = QuantizationMethod::kExact;
  return options;
}

// Every sample at every level: OPTIMAL, valid, never worse than ISP, gap 0, and progress events
// whose bound never exceeds their objective.
TEST(ExactModeTest, ProvesOptimaOnTheSamples) {
  for (const char* file : {"hex-me/s01c_cube.tmesh.json", "hex-me/s02c_prism.tmesh.json",
                           "hex-me/s04u_tetrahedron.tmesh.json", "hex-me/s07c_notch.tmesh.json",
                           "singularity-constrained-fields/fanpart.tmesh.json"}) {
    const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath(file));
    for (const Level& level : mesh.levels()) {
      SCOPED_TRACE(std::string(file) + " level " + std::to_string(level.percent));
      QuantizeOptions isp_options;
      isp_options.scaling = level.scaling;
      const absl::StatusOr<QuantizeResult> isp = Quantize(mesh, isp_options);
      ExactEvents events;
      const absl::StatusOr<QuantizeResult> exact = Quantize(mesh, Exact(level.scaling), &events);
      ASSERT_TRUE(isp.ok() && exact.ok()) << exact.status();
      EXPECT_EQ(exact->termination, Termination::kOptimal);
      ASSERT_TRUE(exact->valid);
      ExpectValid(mesh, exact->q);
      EXPECT_LE(exact->objective, isp->objective + 1e-9);
      ASSERT_TRUE(exact->lower_bound.has_value());
      EXPECT_EQ(*exact->lower_bound, exact->objective);
      EXPECT_EQ(exact->gap, 0.0);
      EXPECT_GE(exact->stats.milp_solves, 1);
      ASSERT_FALSE(events.events.empty());
      for (const ProgressEvent& e : events.events) {
        EXPECT_TRUE(e.separating);
        if (e.lower_bound.has_value()) {
          EXPECT_LE(*e.lower_bound, e.objective + 1e-9);
        }
      }
    }
  }
}

// On tiny grid meshes the proven optimum is the brute-force one.
TEST(ExactModeTest, EqualsTheEnumeratedOptimumOnGridMeshes) {
  testing::GridLayout2D t_junction;
  t_junction.blocks = {{{0, 0}, {2, 1}}, {{0, 1}, {1, 2}}, {{1, 1}, {2, 2}}};
  t_junction.spacing = {std::vector<double>{1.4, 1.4}, std::vector<double>{1.0, 1.0}};
  testing::GridLayout2D l_shape;
  l_shape.blocks = {{{0, 0}, {1, 1}}, {{1, 0}, {2, 1}}, {{0, 1}, {1, 2}}};
  l_shape.spacing = {std::vector<double>{0.8, 2.6}, std::vector<double>{1.7, 0.6}};
  for (const testing::GridLayout2D& layout : {t_junction, l_shape, testing::SeparationExampleA()}) {
    const TMesh mesh =
        testing::TMeshOrDie(testing::BuildGridTMesh(testing::ExtrudeLayout(layout))->proto());
    for (double scaling : {0.8, 1.3, 2.2}) {
      const absl::StatusOr<testing::EnumeratedOptimum> optimum =
          testing::EnumerateOptimum(mesh, scaling, 1);
      ASSERT_TRUE(optimum.ok()) << optimum.status();
      const absl::StatusOr<QuantizeResult> exact = Quantize(mesh, Exact(scaling));
      ASSERT_TRUE(exact.ok()) << exact.status();
      EXPECT_EQ(exact->termination, Termination::kOptimal);
      EXPECT_NEAR(exact->objective, optimum->objective, 1e-6) << scaling;
      ExpectValid(mesh, exact->q);
    }
  }
}

// s11c_cube_cyl at level 100 from a valid but worse start: exact mode streams the improvements
// it finds, the last one being what it returns.
TEST(ExactModeTest, StreamsImprovementsOverItsStart) {
  const TMesh mesh = RealMesh("s11c_cube_cyl");
  const double scaling = mesh.levels().back().scaling;
  const Start start = AllRowsAtOnceIsp(mesh, scaling);
  ASSERT_FALSE(start.q.empty());
  ExpectValid(mesh, start.q);
  ExactEvents events;
  RunClock clock(nullptr, 60);
  const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
  const absl::StatusOr<ExactOutcome> exact =
      RunExactQuantization(mesh, Exact(scaling), start.q, *solver, ExactTuning{}, &events, clock);
  ASSERT_TRUE(exact.ok()) << exact.status();
  ASSERT_EQ(exact->termination, Termination::kOptimal);
  EXPECT_LT(exact->objective, start.objective - 1e-3);
  ExpectValid(mesh, exact->q);
  ASSERT_FALSE(events.improvements.empty());
  const testing::EnumeratedOptimum& last = events.improvements.back();
  EXPECT_EQ(last.q, exact->q);
  EXPECT_NEAR(last.objective, exact->objective, 1e-9);
  EXPECT_NEAR(testing::QuantizationObjective(mesh, scaling, last.q), last.objective, 1e-6);
  for (const testing::EnumeratedOptimum& improvement : events.improvements) {
    ExpectValid(mesh, improvement.q);
  }
}

// Interrupted at its first event, exact mode returns at once with ISP's valid q and a bound.
TEST(ExactModeTest, InterruptionReturnsTheBestValidQ) {
  const TMesh mesh = RealMesh("s11c_cube_cyl");
  const double scaling = mesh.levels().back().scaling;
  SolveInterrupter interrupter;
  ExactEvents events(&interrupter);
  const absl::StatusOr<QuantizeResult> exact =
      Quantize(mesh, Exact(scaling), &events, &interrupter);
  ASSERT_TRUE(exact.ok()) << exact.status();
  EXPECT_EQ(exact->termination, Termination::kInterrupted);
  ASSERT_TRUE(exact->valid);
  ExpectValid(mesh, exact->q);
  ASSERT_TRUE(exact->lower_bound.has_value());
  EXPECT_LE(*exact->lower_bound, exact->objective);
}

// Solving each MILP to optimality before adding rows (BBC22's loop as written) also ends
// OPTIMAL, but for different rows: the search's rows are sufficient conditions found along the
// loop's path, so another path can exclude more. Here it excludes the improvement that
// restarting at the first invalid incumbent finds, and proves the start optimal for its rows.
TEST(ExactModeTest, BothLoopVariantsProveOptimaForTheirOwnRows) {
  const TMesh mesh = RealMesh("s11c_cube_cyl");
  const QuantizeOptions options = Exact(mesh.levels().back().scaling);
  const Start start = AllRowsAtOnceIsp(mesh, options.scaling);
  ASSERT_FALSE(start.q.empty());
  std::vector<double> objectives;
  for (bool restart : {true, false}) {
    ExactTuning tuning;
    tuning.restart_at_invalid_incumbent = restart;
    RunClock clock(nullptr, 60);
    const std::unique_ptr<MilpSolver> solver = NewCbcMilpSolver();
    const absl::StatusOr<ExactOutcome> outcome =
        RunExactQuantization(mesh, options, start.q, *solver, tuning, nullptr, clock);
    ASSERT_TRUE(outcome.ok()) << outcome.status();
    EXPECT_EQ(outcome->termination, Termination::kOptimal);
    EXPECT_EQ(outcome->lower_bound, outcome->objective);
    EXPECT_LE(outcome->objective, start.objective + 1e-9);
    EXPECT_GE(outcome->milp_solves, 2);
    ExpectValid(mesh, outcome->q);
    objectives.push_back(outcome->objective);
  }
  EXPECT_LT(objectives[0], objectives[1] - 1e-3);
}

// The per-arc switch holds in exact mode too, and the validator checks it.
TEST(ExactModeTest, PerArcNonNegativity) {
  const TMesh mesh =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  QuantizeOptions options = Exact(mesh.levels()[0].scaling);
  options.per_arc_nonnegative = true;
  const absl::StatusOr<QuantizeResult> exact = Quantize(mesh, options);
  ASSERT_TRUE(exact.ok());
  EXPECT_EQ(exact->termination, Termination::kOptimal);
  for (int64_t value : exact->q) EXPECT_GE(value, 0);
  ValidationOptions validation;
  validation.per_arc_lower_bound = 0;
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, exact->q, validation);
  ASSERT_TRUE(report.ok());
  EXPECT_TRUE(report->valid()) << report->Describe();
}

// The API's method: unset and ISP mean ISP, EXACT exact mode; unknown values are refused with
// the field named.
TEST(ExactModeTest, MethodFromTheApi) {
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  v1::QuantizationOptions proto;
  proto.mutable_scaling()->set_factor(1.0);
  EXPECT_EQ(QuantizeOptionsFromProto(proto, mesh)->method, QuantizationMethod::kIsp);
  proto.set_method(v1::METHOD_EXACT);
  EXPECT_EQ(QuantizeOptionsFromProto(proto, mesh)->method, QuantizationMethod::kExact);
  proto.set_method(static_cast<v1::Method>(7));
  const absl::StatusOr<QuantizeOptions> bad = QuantizeOptionsFromProto(proto, mesh);
  EXPECT_EQ(bad.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(bad.status().message().find("method"), std::string::npos);
  proto.set_method(v1::METHOD_ISP);
  proto.set_lower_bound(false);
  EXPECT_EQ(QuantizeOptionsFromProto(proto, mesh)->lower_bound, LowerBoundMode::kNever);
}

}  // namespace
}  // namespace ispq
