// SPDX-License-Identifier: Apache-2.0
// The rows of the separation problem over bundles (paper eqs. 1c-1d) through one ISP run, and their
// roles: the block-extent rows C (and optional per-arc bounds) from the start; the simple rows
// (links, regions), held aside until one is first violated and then activated all at once
// (core/README.md, section The separation loop); and the structural rows the separation search
// finds, each in its default form with its failsafe twin B+ (paper App. B), which stands in for it
// while a subproblem is separated in failsafe mode.
//
// The rows themselves live in an InequalityRows store (core/isp/inequality_rows.h) that the LPs
// read; this class decides which are active. Activating a row that is in no LP yet hands it back
// to be attached (core/isp/subproblem_set.h); one that is refreshes its LP row.
#ifndef ISPQ_CORE_ISP_SEPARATION_ROWS_H_
#define ISPQ_CORE_ISP_SEPARATION_ROWS_H_

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "core/arc_bundles.h"
#include "core/flat_lists.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/sheet_subproblem.h"
#include "core/isp/subproblem_set.h"
#include "core/separation_search.h"
#include "core/tmesh.h"

namespace ispq {

// How many new rows a subproblem takes from one search round: `rows`, and one more per
// `bundles_per_extra_row` of its bundles (0: none).
struct NewRowCap {
  int64_t rows = 2;
  int64_t bundles_per_extra_row = 0;

  int64_t For(const SheetSubproblem& subproblem) const {
    if (bundles_per_extra_row <= 0) return rows;
    return std::max<int64_t>(
        rows, static_cast<int64_t>(subproblem.bundles().size()) / bundles_per_extra_row);
  }
};

class SeparationRows {
 public:
  // Builds C (active from the start, as in the paper's Alg. 1), the per-arc bounds if
  // `per_arc_nonnegative`, and the simple rows held aside. Everything referenced must outlive
  // this object.
  SeparationRows(const TMesh& mesh, const ArcBundles& bundles,
                 const BundleQuantization& quantization, bool per_arc_nonnegative);

  const InequalityRows& store() const { return rows_; }
  // Bundle b moved by delta.
  void OnBundleMoved(BundleId b, int64_t delta) { rows_.OnBundleMoved(b, delta); }
  // Per bundle, whether an always-active row x_b >= 0 exists (core/isp/sheet_subproblem.h).
  std::vector<uint8_t> Floors() const;

  // Violated active rows plus, while they are held aside, violated simple rows.
  int64_t NumViolated() const;
  bool simple_rows_active() const { return simple_active_; }
  bool AnyHeldSimpleRowViolated() const { return NumViolatedHeldSimpleRows() > 0; }
  // Activates every simple row (all or nothing); returns the rows to attach.
  std::vector<int32_t> ActivateSimpleRows(SubproblemSet& subproblems);

  // The rows of one search round so far.
  struct Added {
    int64_t activated = 0;  // rows that became active
    bool dropped = false;   // violations were left over once a subproblem's cap was reached
    // Rows activated per subproblem, and how many subproblems reached their cap.
    absl::flat_hash_map<int32_t, int64_t> activated_in;
    int64_t full_subproblems = 0;
    // Whether every one of `count` subproblems is full and a violation was already dropped: no
    // later violation of the round can change anything, so the search may stop.
    bool Done(int64_t count) const { return dropped && full_subproblems == count; }
  };
  // Adds the rows of a search round in their order, one violation per call, each as a default row
  // with its failsafe twin, until `cap` rows became active in a subproblem; that
  // subproblem's later violations are dropped (a later search finds them again if they are still
  // violated). Appends the rows to attach to `to_attach`.
  void AddViolation(const SeparationViolation& v, const NewRowCap& cap, SubproblemSet& subproblems,
                    std::vector<int32_t>* to_attach, Added* added);
  // AddViolation for every violation of a round.
  Added AddViolations(std::span<const SeparationViolation> violations, const NewRowCap& cap,
                      SubproblemSet& subproblems, std::vector<int32_t>* to_attach);

  // A default row of `subproblem` and the failsafe twin standing in for it.
  using Swap = std::pair<int32_t, int32_t>;
  // Replaces the subproblem's active structural rows by their failsafe twins (App. B).
  std::vector<Swap> UseFailsafeForms(int32_t subproblem_id, SubproblemSet& subproblems);
  // After the failsafe solve: default rows that hold again come back; the others stay replaced,
  // their twin being an equally sufficient condition for the same path.
  void RestoreDefaultForms(std::span<const Swap> swaps, SheetSubproblem& subproblem);

  // The rows of found paths in force now (each in its default or failsafe form), without C and
  // the simple rows: what the run's result is certified against (core/exact/lower_bound.h).
  std::vector<int32_t> ActiveSeparationRows() const;

 private:
  int32_t Add(std::span<const LinearTerm> terms, int64_t rhs, RowOrigin origin, bool active);
  // Activates row r if it is not; a row in no LP yet goes to `to_attach`.
  void Activate(int32_t r, SubproblemSet& subproblems, std::vector<int32_t>* to_attach);
  int64_t NumViolatedHeldSimpleRows() const;

  const ArcBundles& bundles_;
  const BundleQuantization& quantization_;
  InequalityRows rows_;
  std::vector<uint8_t> floor_;  // per bundle
  // Simple rows over bundles, until activated.
  FlatLists<LinearTerm> simple_terms_;
  std::vector<int64_t> simple_rhs_;
  bool simple_active_ = false;
  // Per row: the failsafe twin of a structural row; whether the row is the default form of some
  // found path; whether it is required in its own right (C and simple rows), so that the
  // failsafe bookkeeping never switches it off.
  std::vector<int32_t> failsafe_of_;
  std::vector<uint8_t> is_default_;
  std::vector<uint8_t> required_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_SEPARATION_ROWS_H_
