// SPDX-License-Identifier: Apache-2.0
#include "core/isp/separation_rows.h"

#include <algorithm>
#include <optional>

#include "absl/container/flat_hash_map.h"
#include "core/block_extents.h"
#include "core/bundle_row_pair.h"
#include "core/simple_constraints.h"

namespace ispq {

SeparationRows::SeparationRows(const TMesh& mesh, const ArcBundles& bundles,
                               const BundleQuantization& quantization, bool per_arc_nonnegative)
    : bundles_(bundles),
      quantization_(quantization),
      rows_(bundles.num_bundles()),
      floor_(bundles.num_bundles(), 0) {
  // C (eq. 1d, block form): three extent rows per block, as in the paper.
  std::vector<LinearTerm> arc_terms, terms;
  for (BlockId b = 0; b < mesh.num_blocks(); ++b) {
    for (int axis = 0; axis < 3; ++axis) {
      arc_terms.clear();
      for (ArcId a : ExtentRowArcs(mesh, b, axis)) arc_terms.push_back({a, 1});
      terms = bundles.ToBundleTerms(arc_terms);
      if (terms.empty() || rows_.Find(terms, 0) != kNoId) continue;
      Add(terms, 0, RowOrigin::kBlockExtent, true);
    }
  }
  if (per_arc_nonnegative) {
    for (BundleId b = 0; b < bundles.num_bundles(); ++b) {
      const LinearTerm term{b, 1};
      if (rows_.Find({&term, 1}, 0) != kNoId) continue;  // the bundle's extent row says the same
      Add({&term, 1}, 0, RowOrigin::kArcLowerBound, true);
    }
  }
  // Simple rows (links, regions; their block rows coincide with C), held aside.
  for (const SimpleRow& simple : BuildSimpleRows(mesh, std::nullopt)) {
    terms = bundles.ToBundleTerms(simple.row.terms);
    if (terms.empty()) continue;
    simple_terms_.Append(terms);
    simple_rhs_.push_back(simple.row.rhs);
  }
}

int32_t SeparationRows::Add(std::span<const LinearTerm> terms, int64_t rhs, RowOrigin origin,
                            bool active) {
  const int32_t r = rows_.Add(terms, rhs, origin, active, quantization_.values());
  failsafe_of_.push_back(kNoId);
  is_default_.push_back(0);
  const bool required = origin == RowOrigin::kBlockExtent || origin == RowOrigin::kArcLowerBound ||
                        origin == RowOrigin::kSimple;
  required_.push_back(required ? 1 : 0);
  // C and the arc bounds are active for the whole run, so they bound every solve.
  const bool floor = required && origin != RowOrigin::kSimple && terms.size() == 1 &&
                     terms[0].coef > 0 && rhs == 0;
  if (floor) floor_[terms[0].var] = 1;
  return r;
}

std::vector<uint8_t> SeparationRows::Floors() const { return floor_; }

void SeparationRows::Activate(int32_t r, SubproblemSet& subproblems,
                              std::vector<int32_t>* to_attach) {
  if (rows_.active(r)) return;
  rows_.SetActive(r, true);
  if (!subproblems.MarkRowChanged(r)) to_attach->push_back(r);
}

int64_t SeparationRows::NumViolatedHeldSimpleRows() const {
  if (simple_active_) return 0;
  const std::span<const int64_t> x = quantization_.values();
  int64_t violated = 0;
  for (int i = 0; i < simple_terms_.size(); ++i) {
    int64_t value = 0;
    for (const LinearTerm& t : simple_terms_[i]) value += t.coef * x[t.var];
    if (value < simple_rhs_[i]) ++violated;
  }
  return violated;
}

int64_t SeparationRows::NumViolated() const {
  return rows_.num_violated_active() + NumViolatedHeldSimpleRows();
}

std::vector<int32_t> SeparationRows::ActivateSimpleRows(SubproblemSet& subproblems) {
  // All or nothing (core/README.md, section The separation loop): once any simple row is violated,
  // all of them join the active rows for the rest of the run.
  simple_active_ = true;
  std::vector<int32_t> to_attach;
  for (int i = 0; i < simple_terms_.size(); ++i) {
    const int32_t r = rows_.Find(simple_terms_[i], simple_rhs_[i]);
    if (r == kNoId) {
      to_attach.push_back(Add(simple_terms_[i], simple_rhs_[i], RowOrigin::kSimple, true));
      continue;
    }
    required_[r] = 1;
    Activate(r, subproblems, &to_attach);
  }
  return to_attach;
}

SeparationRows::Added SeparationRows::AddViolations(std::span<const SeparationViolation> violations,
                                                    const NewRowCap& cap,
                                                    SubproblemSet& subproblems,
                                                    std::vector<int32_t>* to_attach) {
  Added added;
  for (const SeparationViolation& v : violations) {
    AddViolation(v, cap, subproblems, to_attach, &added);
  }
  return added;
}

void SeparationRows::AddViolation(const SeparationViolation& v, const NewRowCap& cap,
                                  SubproblemSet& subproblems, std::vector<int32_t>* to_attach,
                                  Added* added) {
  const BundleRowPair pair = ToBundleRowPair(bundles_, v.default_row, v.failsafe_row);
  const std::vector<LinearTerm>& failsafe_terms = pair.failsafe_terms;
  if (failsafe_terms.empty()) return;  // cannot happen for +1 rows with terms
  // The cap holds per subproblem (of the row's first bundle): independent parts of a mesh each
  // get their rows in the same round, or a mesh of many parts would need a round per row pair.
  const int32_t id = subproblems.IdOf(failsafe_terms.front().var);
  const int64_t max_new_rows = cap.For(subproblems.at(id));
  int64_t& activated = added->activated_in[id];
  if (activated >= max_new_rows) {
    added->dropped = true;
    return;
  }
  int32_t r = rows_.Find(pair.default_terms, pair.default_rhs);
  bool activates = false;
  if (r == kNoId) {
    r = Add(pair.default_terms, pair.default_rhs, RowOrigin::kStructural, true);
    to_attach->push_back(r);
    activates = true;
  } else if (!rows_.active(r)) {
    Activate(r, subproblems, to_attach);
    activates = true;
  }
  if (activates) {
    ++added->activated;
    if (++activated == max_new_rows) ++added->full_subproblems;
  }
  is_default_[r] = 1;
  if (failsafe_of_[r] == kNoId) {
    int32_t f = rows_.Find(failsafe_terms, pair.failsafe_rhs);
    if (f == kNoId) f = Add(failsafe_terms, pair.failsafe_rhs, RowOrigin::kFailsafe, false);
    failsafe_of_[r] = f;
  }
}

std::vector<SeparationRows::Swap> SeparationRows::UseFailsafeForms(int32_t subproblem_id,
                                                                   SubproblemSet& subproblems) {
  SheetSubproblem& subproblem = subproblems.at(subproblem_id);
  std::vector<Swap> swaps;
  std::vector<int32_t> to_attach;
  const std::vector<int32_t> subproblem_rows = subproblem.rows();
  for (int32_t r : subproblem_rows) {
    if (!is_default_[r] || required_[r] || !rows_.active(r)) continue;
    const int32_t f = failsafe_of_[r];
    if (f == kNoId || f == r) continue;
    rows_.SetActive(r, false);
    subproblem.MarkRowChanged(r);
    Activate(f, subproblems, &to_attach);
    swaps.push_back({r, f});
  }
  subproblems.AttachTo(subproblem_id, to_attach);
  return swaps;
}

void SeparationRows::RestoreDefaultForms(std::span<const Swap> swaps, SheetSubproblem& subproblem) {
  for (const auto& [r, f] : swaps) {
    if (!rows_.violated(r)) {
      rows_.SetActive(r, true);
      subproblem.MarkRowChanged(r);
    }
  }
  // A twin stays while it stands in for any default row of the subproblem, replaced in this
  // failsafe solve or in an earlier one (only UseFailsafeForms switches default rows off).
  std::vector<int32_t> standing_in;
  for (int32_t r : subproblem.rows()) {
    if (is_default_[r] && !rows_.active(r) && failsafe_of_[r] != kNoId) {
      standing_in.push_back(failsafe_of_[r]);
    }
  }
  std::sort(standing_in.begin(), standing_in.end());
  for (const Swap& swap : swaps) {
    const int32_t f = swap.second;
    if (is_default_[f] || required_[f]) continue;
    if (rows_.active(f) && !std::binary_search(standing_in.begin(), standing_in.end(), f)) {
      rows_.SetActive(f, false);
      subproblem.MarkRowChanged(f);
    }
  }
}

std::vector<int32_t> SeparationRows::ActiveSeparationRows() const {
  std::vector<int32_t> active;
  for (int32_t r = 0; r < rows_.size(); ++r) {
    const RowOrigin origin = rows_.origin(r);
    const bool found = origin == RowOrigin::kStructural || origin == RowOrigin::kFailsafe;
    if (found && rows_.active(r) && !required_[r]) active.push_back(r);
  }
  return active;
}

}  // namespace ispq
