// SPDX-License-Identifier: Apache-2.0
// One pump step: the integer sheet of a subproblem's LP vertex, its multiplicity at the vertex of
// the objective, capped by the active rows, refused when a row would break, and nothing at all
// once the run must stop.
#include "core/isp/sheet_step.h"

#include <limits>
#include <vector>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/clp_sheet_lp.h"
#include "core/isp/separation_rows.h"
#include "core/isp/subproblem_set.h"
#include "core/solve_interrupter.h"
#include "core/subproblems.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

// A single block with targets 3, 2 and 1 along u, v and w, at q = 0.
class SheetStepTest : public ::testing::Test {
 protected:
  SheetStepTest()
      : mesh_(Cuboid()),
        consistency_(mesh_),
        bundles_(mesh_, consistency_),
        quantization_(mesh_, bundles_, 1.0),
        initial_(mesh_, consistency_, bundles_),
        rows_(mesh_, bundles_, quantization_, false),
        set_(consistency_, bundles_, initial_, quantization_, rows_.store(), rows_.Floors(),
             mesh_.num_arcs(), ClpSheetLpFactory(), true),
        clock_(&interrupter_, std::numeric_limits<double>::infinity()),
        finder_(quantization_, rows_.store(), tuning_, clock_, stats_) {}

  static TMesh Cuboid() {
    testing::GridTMeshSpec spec;
    spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
    spec.spacing = {{{3.0}, {2.0}, {1.0}}};
    return testing::TMeshOrDie(testing::BuildGridTMesh(spec)->proto());
  }
  BundleId U() const {
    return bundles_.bundle_of(mesh_.block_edge_arcs(0, EdgeCode(0, false, false))[0]);
  }
  SheetRequest InflateU() const {
    SheetRequest request;
    request.root = U();
    request.inflate_root = true;
    return request;
  }
  // Adds and attaches a structural row over the u edges' arcs: coef * q_u >= rhs.
  void AddURow(int coef, int64_t rhs) {
    SeparationViolation v;
    const ArcId arc = mesh_.block_edge_arcs(0, EdgeCode(0, false, false))[0];
    v.default_row = {{{arc, coef}}, rhs};
    v.failsafe_row = {{{arc, 1}}, 1};
    std::vector<int32_t> attach;
    rows_.AddViolations({&v, 1}, {.rows = 1}, set_, &attach);
    set_.Attach(attach);
  }

  const TMesh mesh_;
  const ConsistencyMatrix consistency_;
  const ArcBundles bundles_;
  BundleQuantization quantization_;
  const Subproblems initial_;
  SeparationRows rows_;
  SubproblemSet set_;
  SolveInterrupter interrupter_;
  RunClock clock_;
  IspTuning tuning_;
  QuantizeStats stats_;
  SheetStepFinder finder_;
};

TEST_F(SheetStepTest, StepsToTheVertexOfTheObjective) {
  SheetStep step;
  ASSERT_TRUE(*finder_.Find(set_.Of(U()), InflateU(), &step));
  ASSERT_EQ(step.sheet.bundles, std::vector<BundleId>{U()});
  EXPECT_EQ(step.sheet.deltas, std::vector<int64_t>{1});
  EXPECT_EQ(step.t, 3);  // each of the 4 u arcs from 0 to its target 3
  EXPECT_DOUBLE_EQ(step.gain, 4 * (0.0 - 9.0));
  EXPECT_EQ(stats_.lp_solves, 1);
  EXPECT_EQ(stats_.lcd_one, 1);
}

TEST_F(SheetStepTest, ActiveRowsCapTheMultiplicity) {
  AddURow(-1, -2);  // q_u <= 2
  SheetStep step;
  ASSERT_TRUE(*finder_.Find(set_.Of(U()), InflateU(), &step));
  EXPECT_EQ(step.t, 2);
}

TEST_F(SheetStepTest, NoStepWhereTheRowsLeaveNoRoom) {
  AddURow(-1, 0);  // q_u <= 0: the root cannot inflate at all
  SheetStep step;
  EXPECT_FALSE(*finder_.Find(set_.Of(U()), InflateU(), &step));
}

TEST_F(SheetStepTest, NothingOnceTheRunMustStop) {
  interrupter_.Interrupt();
  SheetStep step;
  EXPECT_FALSE(*finder_.Find(set_.Of(U()), InflateU(), &step));
  EXPECT_EQ(stats_.lp_solves, 0);
  EXPECT_EQ(clock_.termination(), Termination::kInterrupted);
}

}  // namespace
}  // namespace ispq
