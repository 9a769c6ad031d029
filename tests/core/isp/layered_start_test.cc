// SPDX-License-Identifier: Apache-2.0
#include "core/isp/layered_start.h"

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/quantization_objective.h"
#include "core/quantization_progress.h"
#include "core/quantization_validator.h"
#include "core/quantize_result.h"
#include "core/run_clock.h"
#include "core/tmesh.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

class Recorder : public ProgressObserver {
 public:
  explicit Recorder(bool wants_q) : wants_q_(wants_q) {}
  void OnProgress(const ProgressEvent& event) override {
    events.push_back(event);
    qs.emplace_back(event.q.begin(), event.q.end());
  }
  bool WantsQuantization() const override { return wants_q_; }
  std::vector<ProgressEvent> events;
  std::vector<std::vector<int64_t>> qs;

 private:
  bool wants_q_;
};

struct Layered {
  std::optional<ValidStart> start;
  std::vector<int64_t> q;  // per arc, if found
  QuantizeStats stats;
};

Layered Find(const TMesh& mesh, double scaling, ProgressObserver* observer,
             QuantizeStats stats = {}) {
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const BundleQuantization quantization(mesh, bundles, scaling);
  const RunClock clock(nullptr, std::numeric_limits<double>::infinity());
  Layered result;
  result.stats = stats;
  result.start = FindLayeredStart(mesh, consistency, bundles, quantization, scaling, clock,
                                  result.stats, observer);
  if (result.start.has_value()) result.q = bundles.ArcValues(result.start->values);
  return result;
}

// Two blocks along u with a T-junction on top: the layers give q >= 1, valid, reported once.
TEST(LayeredStartTest, AValidLayeredQIsReportedAsTheFirstValidQ) {
  testing::GridLayout2D layout;
  layout.blocks = {{{0, 0}, {2, 1}}, {{0, 1}, {1, 2}}, {{1, 1}, {2, 2}}};
  layout.spacing = {std::vector<double>{2.6, 0.8}, std::vector<double>{1.2, 3.1}};
  const testing::GridTMesh grid = *testing::BuildGridTMesh(testing::ExtrudeLayout(layout));
  const TMesh mesh = testing::TMeshOrDie(grid.proto());
  for (double scaling : {0.5, 1.0, 3.0}) {
    SCOPED_TRACE(scaling);
    Recorder recorder(/*wants_q=*/true);
    const Layered layered = Find(mesh, scaling, &recorder);
    ASSERT_TRUE(layered.start.has_value());
    for (int64_t x : layered.q) EXPECT_GE(x, 1);
    const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, layered.q);
    ASSERT_TRUE(report.ok());
    EXPECT_TRUE(report->valid()) << report->Describe();
    EXPECT_DOUBLE_EQ(layered.start->objective, QuantizationObjective(mesh, layered.q, scaling));
    ASSERT_EQ(recorder.events.size(), 1u);
    const ProgressEvent& event = recorder.events[0];
    EXPECT_EQ(event.phase, QuantizationPhase::kLayers);
    EXPECT_EQ(event.iteration, 0);
    EXPECT_EQ(event.separation_round, 0);
    EXPECT_EQ(event.violated_constraints, 0);
    EXPECT_TRUE(event.separating);
    EXPECT_DOUBLE_EQ(event.objective, layered.start->objective);
    EXPECT_EQ(recorder.qs[0], layered.q);
  }
}

// An observer that does not want q gets the event without it; none at all is fine too. The
// stats accumulate rather than being overwritten.
TEST(LayeredStartTest, ReportsWithoutQUnlessAskedAndAddsToTheStats) {
  const TMesh cube = testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s01c_cube.tmesh.json"));
  Recorder recorder(/*wants_q=*/false);
  QuantizeStats before;
  before.layers_seconds = 100;
  before.separation_search_seconds = 200;
  const Layered layered = Find(cube, 1.0, &recorder, before);
  ASSERT_TRUE(layered.start.has_value());
  ASSERT_EQ(recorder.events.size(), 1u);
  EXPECT_TRUE(recorder.qs[0].empty());
  EXPECT_GE(layered.stats.layers_seconds, 100);
  EXPECT_GE(layered.stats.separation_search_seconds, 200);
  const Layered unobserved = Find(cube, 1.0, nullptr);
  ASSERT_TRUE(unobserved.start.has_value());
  EXPECT_EQ(unobserved.start->values, layered.start->values);
}

// On the one real mesh whose layers spiral there is no layered start, and nothing is reported.
TEST(LayeredStartTest, NoStartWhereTheLayersDoNotClose) {
  const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath(
      "metamesh-guided-hexalab/"
      "2017_-_Explicit_Cylindrical_Maps_for_General_Tubular_Shapes_femur_shell1.tmesh.json"));
  Recorder recorder(/*wants_q=*/true);
  EXPECT_FALSE(Find(mesh, mesh.levels().back().scaling, &recorder).start.has_value());
  EXPECT_TRUE(recorder.events.empty());
}

// On real meshes whose layers close, the start is valid by the validator at every level.
TEST(LayeredStartTest, ValidOnRealMeshes) {
  for (const char* file :
       {"hex-me/s07c_notch.tmesh.json", "singularity-constrained-fields/fanpart.tmesh.json"}) {
    SCOPED_TRACE(file);
    const TMesh mesh = testing::LoadTMeshOrDie(testing::RealTMeshPath(file));
    for (const Level& level : mesh.levels()) {
      const Layered layered = Find(mesh, level.scaling, nullptr);
      ASSERT_TRUE(layered.start.has_value()) << level.percent;
      const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, layered.q);
      ASSERT_TRUE(report.ok());
      EXPECT_TRUE(report->valid()) << level.percent << ": " << report->Describe();
    }
  }
}

}  // namespace
}  // namespace ispq
