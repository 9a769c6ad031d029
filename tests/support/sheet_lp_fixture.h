// SPDX-License-Identifier: Apache-2.0
// One sheet LP over a whole mesh, wired as the quantizer wires it (bundles, the quantization,
// the consistency rows over bundles, optionally the block-extent rows C), for tests of the
// subproblem LP (core/isp/sheet_subproblem.h) and of what it relies on.
#ifndef ISPQ_TESTS_SUPPORT_SHEET_LP_FIXTURE_H_
#define ISPQ_TESTS_SUPPORT_SHEET_LP_FIXTURE_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/arc_bundles.h"
#include "core/bundle_potentials.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/sheet_lp.h"
#include "core/isp/sheet_subproblem.h"
#include "core/tmesh.h"

namespace ispq::testing {

struct SheetLpFixtureOptions {
  bool extent_rows = true;
  double column_cap = SheetLpContext{}.column_cap;
  bool refute_by_propagation = true;
  SheetLpFactory new_lp = nullptr;  // CLP
  // Requests without a root are first solved as flows (SheetLpContext::potentials); the mesh
  // must have potentials (core/bundle_potentials.h).
  bool flows = false;
};

class SheetLpFixture {
 public:
  SheetLpFixture(const TMesh& mesh, double scaling, const SheetLpFixtureOptions& options = {});

  // Appends an inequality row sum terms >= rhs to the store (not to the LP: see lp().AddRows).
  int32_t AddRow(const std::vector<LinearTerm>& terms, int64_t rhs, bool active);
  // Moves bundles as the driver does: values, row values, LP bookkeeping.
  void Apply(const IntegerSheet& sheet);

  const ArcBundles& bundles() const { return bundles_; }
  const FlatLists<LinearTerm>& equalities() const { return equalities_; }
  const BundleQuantization& quantization() const { return x_; }
  SheetSubproblem& lp() { return *lp_; }
  InequalityRows& rows() { return rows_; }

 private:
  ConsistencyMatrix consistency_;
  ArcBundles bundles_;
  BundleQuantization x_;
  InequalityRows rows_;
  FlatLists<LinearTerm> equalities_;
  std::optional<BundlePotentials> potentials_;
  SheetLpContext context_;
  std::unique_ptr<SheetSubproblem> lp_;
};

// A request pumping `root` up (inflate) or down.
SheetRequest Pump(BundleId root, bool inflate);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_SUPPORT_SHEET_LP_FIXTURE_H_
