// SPDX-License-Identifier: Apache-2.0
#include "tests/support/sheet_lp_fixture.h"

#include <utility>

#include "core/block_extents.h"
#include "core/invariant.h"
#include "core/isp/clp_sheet_lp.h"

namespace ispq::testing {

SheetLpFixture::SheetLpFixture(const TMesh& mesh, double scaling,
                               const SheetLpFixtureOptions& options)
    : consistency_(mesh),
      bundles_(mesh, consistency_),
      x_(mesh, bundles_, scaling),
      rows_(bundles_.num_bundles()) {
  std::vector<int32_t> equalities;
  for (int r = 0; r < consistency_.num_rows(); ++r) {
    const std::vector<LinearTerm> terms = bundles_.ToBundleTerms(consistency_.row(r));
    if (terms.empty()) continue;
    equalities.push_back(equalities_.size());
    equalities_.Append(terms);
  }
  context_.quantization = &x_;
  context_.rows = &rows_;
  context_.equalities = &equalities_;
  context_.num_arcs = mesh.num_arcs();
  context_.column_cap = options.column_cap;
  context_.refute_by_propagation = options.refute_by_propagation;
  context_.new_lp = options.new_lp ? options.new_lp : ClpSheetLpFactory();
  context_.local_index_of_bundle.assign(bundles_.num_bundles(), kNoId);
  context_.has_floor.assign(bundles_.num_bundles(), 0);
  if (options.flows) {
    potentials_ = BundlePotentials::Compute(mesh, consistency_, bundles_);
    ISPQ_RELEASE_INVARIANT(potentials_.has_value(), "a fixture with flows needs potentials");
    context_.potentials = &*potentials_;
  }
  std::vector<int32_t> row_ids;
  if (options.extent_rows) {
    for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
      for (int axis = 0; axis < 3; ++axis) {
        std::vector<LinearTerm> arc_terms;
        for (ArcId a : ExtentRowArcs(mesh, b, axis)) arc_terms.push_back({a, 1});
        const std::vector<LinearTerm> terms = bundles_.ToBundleTerms(arc_terms);
        if (rows_.Find(terms, 0) != kNoId) continue;
        row_ids.push_back(AddRow(terms, 0, true));
        if (terms.size() == 1) context_.has_floor[terms[0].var] = 1;
      }
    }
  }
  std::vector<BundleId> all(bundles_.num_bundles());
  for (BundleId b = 0; b < bundles_.num_bundles(); ++b) all[b] = b;
  lp_ = std::make_unique<SheetSubproblem>(&context_, all, equalities, row_ids);
}

int32_t SheetLpFixture::AddRow(const std::vector<LinearTerm>& terms, int64_t rhs, bool active) {
  context_.lp_row_of_row.push_back(kNoId);
  return rows_.Add(terms, rhs, RowOrigin::kStructural, active, x_.values());
}

void SheetLpFixture::Apply(const IntegerSheet& sheet) {
  x_.Apply(sheet, 1);
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    rows_.OnBundleMoved(sheet.bundles[i], sheet.deltas[i]);
    lp_->MarkBundleMoved(sheet.bundles[i]);
  }
}

SheetRequest Pump(BundleId root, bool inflate) {
  SheetRequest request;
  request.root = root;
  request.inflate_root = inflate;
  return request;
}

}  // namespace ispq::testing
