#include "core/isp/integer_sheet_pump.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <queue>
#include <span>
#include <unordered_map>
#include <utility>

#include "absl/status/status.h"
#include "core/arc_bundles.h"
#include "core/block_extents.h"
#include "core/consistency_matrix.h"
#include "core/disjoint_sets.h"
#include "core/flat_lists.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/integer_sheet.h"
#include "core/isp/integer_step.h"
#include "core/isp/lcd_scaling.h"
#include "core/isp/sheet_subproblem.h"
#include "core/separation_check.h"
#include "core/simple_constraints.h"
#include "core/subproblems.h"

namespace ispq {
namespace {

using Clock = std::chrono::steady_clock;

// Effectively unbounded multiplicity; the objective's vertex bounds real steps long before.
constexpr int64_t kUnboundedStep = int64_t{1} << 40;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Adds the lifetime of the scope to a stats field.
class ScopedSeconds {
 public:
  explicit ScopedSeconds(double* sink) : sink_(sink), start_(Clock::now()) {}
  ~ScopedSeconds() { *sink_ += SecondsSince(start_); }

 private:
  double* sink_;
  Clock::time_point start_;
};

struct RootEntry {
  double priority;
  BundleId bundle;
  int32_t stamp;
};

// Max-heap on priority; among equal priorities the smaller bundle id first (determinism).
struct RootOrder {
  bool operator()(const RootEntry& x, const RootEntry& y) const {
    if (x.priority != y.priority) return x.priority < y.priority;
    return x.bundle > y.bundle;
  }
};

// A candidate update: an integer sheet, its multiplicity and the objective change.
struct Step {
  IntegerSheet sheet;
  int64_t t = 0;
  double gain = 0;
};

class IntegerSheetPump {
 public:
  IntegerSheetPump(const TMesh& mesh, const QuantizeOptions& options, const IspTuning& tuning,
                   ProgressObserver* observer, const SolveInterrupter* interrupter)
      : mesh_(mesh),
        options_(options),
        tuning_(tuning),
        observer_(observer),
        interrupter_(interrupter),
        start_(Clock::now()),
        consistency_(mesh),
        bundles_(mesh, consistency_),
        quantization_(mesh, bundles_, options.scaling),
        rows_(bundles_.num_bundles()) {}

  absl::StatusOr<IspOutcome> Run();

 private:
  // ---- Set-up ----
  void BuildEqualities();
  void BuildInitialRows();
  void BuildSubproblems();
  int32_t AddRow(std::span<const LinearTerm> terms, int64_t rhs, RowOrigin origin, bool active);
  void MarkFloorRow(int32_t r);

  // ---- Control ----
  bool ShouldStop();
  double Tolerance() const { return 1e-9 * (1.0 + std::abs(quantization_.objective())); }

  // ---- Sheets ----
  SheetSubproblem& GroupOf(BundleId b) { return *groups_[group_of_bundle_[b]]; }
  absl::StatusOr<bool> SolveRational(SheetSubproblem& group, const SheetRequest& request);
  absl::Status DiveToInteger(SheetSubproblem& group, const SheetRequest& request);
  absl::StatusOr<bool> ComputeStep(SheetSubproblem& group, const SheetRequest& request, Step* step);
  bool RowsAllowStep(const IntegerSheet& sheet, int64_t* t_max);
  void Apply(const Step& step);

  // ---- Phases ----
  absl::StatusOr<bool> Greedy(bool thorough, QuantizationPhase phase);
  void PushRoot(BundleId b);
  void RecordDependencies(BundleId root, std::span<const BundleId> support);
  void InvalidateAfter(const IntegerSheet& sheet);
  absl::StatusOr<bool> SeparatingUpdate();
  absl::StatusOr<bool> SeparateGroup(int32_t g);
  absl::StatusOr<bool> FailsafeGroup(int32_t g);

  // ---- Separation rows ----
  bool AnySimpleRowViolated() const;
  std::vector<int32_t> ActivateSimpleRows();
  absl::StatusOr<int64_t> SearchRound(std::vector<int32_t>* new_rows);
  void AttachRows(const std::vector<int32_t>& new_rows);

  // ---- Reporting ----
  void Report(QuantizationPhase phase);
  void SaveIfBestValid();
  IspOutcome Finish();

  const TMesh& mesh_;
  const QuantizeOptions& options_;
  const IspTuning& tuning_;
  ProgressObserver* observer_;
  const SolveInterrupter* interrupter_;
  Clock::time_point start_;

  ConsistencyMatrix consistency_;
  ArcBundles bundles_;
  BundleQuantization quantization_;
  InequalityRows rows_;
  FlatLists<LinearTerm> equalities_;  // consistency rows over bundles, deduplicated
  std::vector<int32_t> equality_component_;
  std::optional<Subproblems> components_;
  // Reference search first, then the sorted one (core/separation_check.h): the laxer search's
  // rows come first, and every row the sorted search adds early on, for a q that is later left
  // anyway, constrains the rest of the run.
  std::optional<SeparationCheck> separation_;

  // Simple rows over bundles, activated all at once when one is first violated.
  FlatLists<LinearTerm> simple_terms_;
  std::vector<int64_t> simple_rhs_;
  bool simple_active_ = false;

  // Per row: the failsafe twin of a structural row; whether the row is the default form of some
  // found path; whether it is required in its own right (C and simple rows), so that the
  // failsafe bookkeeping never switches it off.
  std::vector<int32_t> failsafe_of_;
  std::vector<uint8_t> is_default_;
  std::vector<uint8_t> required_;

  SheetLpContext context_;
  std::vector<std::unique_ptr<SheetSubproblem>> groups_;  // null once merged into another
  std::vector<int32_t> group_of_bundle_;

  // Greedy bookkeeping: heap stamps and, per bundle, the roots whose last sheet involved it.
  std::priority_queue<RootEntry, std::vector<RootEntry>, RootOrder> heap_;
  std::vector<int32_t> stamp_;
  std::vector<std::vector<std::pair<BundleId, int32_t>>> users_;
  std::vector<uint32_t> bundle_mark_;
  uint32_t mark_epoch_ = 0;

  // Scratch.
  RationalSheet rational_;
  std::optional<int64_t> lcd_;  // of rational_
  std::vector<std::pair<BundleId, bool>> blocked_;
  Step step_;
  std::vector<int64_t> row_delta_;
  std::vector<uint8_t> row_touched_;
  std::vector<int32_t> touched_rows_;
  std::vector<int64_t> arc_values_;

  // Run state.
  bool stop_ = false;
  Termination termination_ = Termination::kConverged;
  bool changed_since_search_ = true;
  bool search_clean_ = false;  // the current q passed the simple rows and a search
  int64_t accepted_sheets_ = 0;
  bool has_valid_ = false;
  double best_valid_objective_ = 0;
  std::vector<int64_t> best_valid_values_;
  QuantizeStats stats_;
};

// ---------------------------------------------------------------------------------------------
// Set-up

void IntegerSheetPump::MarkFloorRow(int32_t r) {
  // Only rows active for the whole run say anything about every solve.
  const std::span<const LinearTerm> terms = rows_.terms(r);
  if (!tuning_.extent_rows_from_start || terms.size() != 1 || terms[0].coef <= 0 ||
      rows_.rhs(r) != 0) {
    return;
  }
  context_.has_floor[terms[0].var] = 1;
}

int32_t IntegerSheetPump::AddRow(std::span<const LinearTerm> terms, int64_t rhs, RowOrigin origin,
                                 bool active) {
  const int32_t r = rows_.Add(terms, rhs, origin, active, quantization_.values());
  failsafe_of_.push_back(kNoId);
  is_default_.push_back(0);
  required_.push_back(origin == RowOrigin::kBlockExtent || origin == RowOrigin::kArcLowerBound ||
                              origin == RowOrigin::kSimple
                          ? 1
                          : 0);
  context_.lp_row_of_row.push_back(kNoId);
  row_delta_.push_back(0);
  row_touched_.push_back(0);
  return r;
}

void IntegerSheetPump::BuildEqualities() {
  // Rows that bundling made trivial are dropped (section 4.4); rows that became identical up to
  // sign are kept once.
  std::unordered_map<uint64_t, std::vector<int32_t>> by_hash;
  std::vector<LinearTerm> terms;
  for (int r = 0; r < consistency_.num_rows(); ++r) {
    terms = bundles_.ToBundleTerms(consistency_.row(r));
    if (terms.empty()) continue;
    if (terms[0].coef < 0) {
      for (LinearTerm& t : terms) t.coef = -t.coef;
    }
    uint64_t h = 1469598103934665603ull;
    for (const LinearTerm& t : terms) {
      h = (h ^ static_cast<uint32_t>(t.var)) * 1099511628211ull;
      h = (h ^ static_cast<uint32_t>(t.coef)) * 1099511628211ull;
    }
    std::vector<int32_t>& same = by_hash[h];
    const bool duplicate = std::any_of(same.begin(), same.end(), [&](int32_t e) {
      const std::span<const LinearTerm> other = equalities_[e];
      return std::equal(terms.begin(), terms.end(), other.begin(), other.end(),
                        [](const LinearTerm& x, const LinearTerm& y) {
                          return x.var == y.var && x.coef == y.coef;
                        });
    });
    if (duplicate) continue;
    same.push_back(equalities_.size());
    equalities_.Append(terms);
    equality_component_.push_back(components_->subproblem_of(terms[0].var));
  }
}

void IntegerSheetPump::BuildInitialRows() {
  // C (eq. 1d, block form): three extent rows per block from the start, as in the paper.
  std::vector<LinearTerm> arc_terms, terms;
  for (BlockId b = 0; b < mesh_.num_blocks(); ++b) {
    for (int axis = 0; axis < 3; ++axis) {
      arc_terms.clear();
      for (ArcId a : ExtentRowArcs(mesh_, b, axis)) arc_terms.push_back({a, 1});
      terms = bundles_.ToBundleTerms(arc_terms);
      if (terms.empty() || rows_.Find(terms, 0) != kNoId) continue;
      const int32_t r = AddRow(terms, 0, RowOrigin::kBlockExtent, tuning_.extent_rows_from_start);
      MarkFloorRow(r);
    }
  }
  if (options_.per_arc_nonnegative) {
    for (BundleId b = 0; b < bundles_.num_bundles(); ++b) {
      const LinearTerm term{b, 1};
      const int32_t r = rows_.Find({&term, 1}, 0);
      if (r != kNoId) continue;  // the bundle's own extent row says the same
      MarkFloorRow(
          AddRow({&term, 1}, 0, RowOrigin::kArcLowerBound, tuning_.extent_rows_from_start));
    }
  }
  // Simple separation rows (links, regions; block rows coincide with C), kept aside until one
  // is violated (separation.md section 2.5).
  for (const SimpleRow& simple : BuildSimpleRows(mesh_, std::nullopt)) {
    terms = bundles_.ToBundleTerms(simple.row.terms);
    if (terms.empty()) continue;
    simple_terms_.Append(terms);
    simple_rhs_.push_back(simple.row.rhs);
  }
}

void IntegerSheetPump::BuildSubproblems() {
  const int nb = bundles_.num_bundles();
  context_.quantization = &quantization_;
  context_.rows = &rows_;
  context_.equalities = &equalities_;
  context_.num_arcs = static_cast<double>(mesh_.num_arcs());
  const ClpSheetLpOptions lp_options = tuning_.lp;
  context_.new_lp = [lp_options](int num_columns) {
    return NewClpSheetLp(num_columns, lp_options);
  };
  context_.local_index_of_bundle.assign(nb, kNoId);
  group_of_bundle_.assign(nb, kNoId);

  const int num_groups = options_.decompose ? components_->num_subproblems() : 1;
  auto group_of_component = [&](int32_t c) { return options_.decompose ? c : 0; };
  std::vector<std::vector<BundleId>> bundles(num_groups);
  std::vector<std::vector<int32_t>> equalities(num_groups), rows(num_groups);
  for (BundleId b = 0; b < nb; ++b) {
    bundles[group_of_component(components_->subproblem_of(b))].push_back(b);
  }
  for (int32_t e = 0; e < equalities_.size(); ++e) {
    equalities[group_of_component(equality_component_[e])].push_back(e);
  }
  for (int32_t r = 0; r < rows_.size(); ++r) {
    rows[group_of_component(components_->subproblem_of(rows_.terms(r)[0].var))].push_back(r);
  }
  for (int g = 0; g < num_groups; ++g) {
    for (BundleId b : bundles[g]) group_of_bundle_[b] = g;
    groups_.push_back(std::make_unique<SheetSubproblem>(
        &context_, std::move(bundles[g]), std::move(equalities[g]), std::move(rows[g])));
  }
}

// ---------------------------------------------------------------------------------------------
// Control

bool IntegerSheetPump::ShouldStop() {
  if (stop_) return true;
  if (interrupter_ != nullptr && interrupter_->IsInterrupted()) {
    stop_ = true;
    termination_ = Termination::kInterrupted;
  } else if (SecondsSince(start_) > options_.time_limit_seconds) {
    stop_ = true;
    termination_ = Termination::kTimeLimit;
  }
  return stop_;
}

// ---------------------------------------------------------------------------------------------
// Sheets

absl::StatusOr<bool> IntegerSheetPump::SolveRational(SheetSubproblem& group,
                                                     const SheetRequest& request) {
  const int64_t calls = group.solver_calls();
  absl::StatusOr<bool> feasible = group.Solve(request, &rational_);
  stats_.lp_solves += group.solver_calls() - calls;
  if (!feasible.ok()) return feasible.status();
  if (!*feasible || rational_.bundles.empty()) return false;
  // Paper Fig. 8 counts the denominators of every rational solution computed.
  lcd_ = LeastCommonDenominator(rational_.values);
  if (!lcd_.has_value() || *lcd_ > 2) {
    ++stats_.lcd_more;
  } else if (*lcd_ == 2) {
    ++stats_.lcd_two;
  } else {
    ++stats_.lcd_one;
  }
  return true;
}

absl::Status IntegerSheetPump::DiveToInteger(SheetSubproblem& group, const SheetRequest& request) {
  SheetRequest dive = request;
  std::vector<std::pair<BundleId, int64_t>> fixed(request.fixed.begin(), request.fixed.end());
  RationalSheet last = rational_;
  std::optional<int64_t> last_lcd = lcd_;
  // Every iteration pins one more bundle, so the dive ends after at most one solve per bundle.
  const size_t max_pins =
      std::min(group.bundles().size(), static_cast<size_t>(std::max(tuning_.max_dive_pins, 0)));
  for (size_t pinned = 0; pinned < max_pins && lcd_.has_value() && *lcd_ > 1 && !ShouldStop();
       ++pinned) {
    // Pin the fractional bundle closest to its next integer away from zero to that integer.
    BundleId best = kNoId;
    double best_gap = 2, best_value = 0;
    for (size_t i = 0; i < rational_.bundles.size(); ++i) {
      const double v = rational_.values[i];
      const double gap = std::ceil(std::abs(v)) - std::abs(v);
      if (gap > 1e-6 && gap < best_gap) {
        best_gap = gap;
        best = rational_.bundles[i];
        best_value = v;
      }
    }
    if (best == kNoId) break;
    const int64_t magnitude = static_cast<int64_t>(std::ceil(std::abs(best_value)));
    fixed.push_back({best, best_value > 0 ? magnitude : -magnitude});
    dive.fixed = fixed;
    absl::StatusOr<bool> feasible = SolveRational(group, dive);
    if (!feasible.ok()) return feasible.status();
    if (!*feasible) {
      // The pinned vertex does not exist: scale the last rational solution instead.
      rational_ = std::move(last);
      lcd_ = last_lcd;
      return absl::OkStatus();
    }
    last = rational_;
    last_lcd = lcd_;
  }
  return absl::OkStatus();
}

absl::StatusOr<bool> IntegerSheetPump::ComputeStep(SheetSubproblem& group,
                                                   const SheetRequest& request, Step* step) {
  if (ShouldStop()) return false;
  absl::StatusOr<bool> feasible = SolveRational(group, request);
  if (!feasible.ok()) return feasible.status();
  if (!*feasible) return false;

  // Rational vertex -> integer sheet (section 4.3.1): optionally dive to an integer vertex
  // first, then multiply by the least common denominator.
  if (tuning_.integer_dive && lcd_.has_value() && *lcd_ > 1) {
    const absl::Status dived = DiveToInteger(group, request);
    if (!dived.ok()) return dived;
  }
  if (!lcd_.has_value()) return false;
  const int64_t lcd = *lcd_;
  IntegerSheet& sheet = step->sheet;
  sheet.Clear();
  sheet.lcd = lcd;
  for (size_t i = 0; i < rational_.bundles.size(); ++i) {
    const int64_t d = std::llround(rational_.values[i] * static_cast<double>(lcd));
    if (d == 0) continue;
    sheet.bundles.push_back(rational_.bundles[i]);
    sheet.deltas.push_back(d);
  }
  if (sheet.empty() || !group.IsConsistent(sheet)) return false;

  // The scaled sheet must still satisfy every active row (Alg. 2/3: "if Delta q violates (7c)
  // or (7d)"); the rows also bound its multiplicity.
  int64_t t_max = kUnboundedStep;
  if (!RowsAllowStep(sheet, &t_max)) return false;

  // OPTIMALINTEGERSTEP: the vertex of the convex objective along the sheet, clamped to [1, t_max].
  const StepQuadratic f = quantization_.Quadratic(sheet);
  double a = f.a, b = f.b;
  if (tuning_.step_damping < 1) {
    const double vertex = -b / (2 * a);
    const double damped = std::max(std::min(0.5, vertex), tuning_.step_damping * vertex);
    b = -2 * a * damped;
  }
  step->t = OptimalIntegerStep(a, b, 1, t_max);
  step->gain = f.At(step->t);
  return true;
}

bool IntegerSheetPump::RowsAllowStep(const IntegerSheet& sheet, int64_t* t_max) {
  touched_rows_.clear();
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    for (const InequalityRows::Incidence& inc : rows_.rows_of_bundle(sheet.bundles[i])) {
      if (!row_touched_[inc.row]) {
        row_touched_[inc.row] = 1;
        touched_rows_.push_back(inc.row);
      }
      row_delta_[inc.row] += inc.coef * sheet.deltas[i];
    }
  }
  bool ok = true;
  for (int32_t r : touched_rows_) {
    const int64_t d = row_delta_[r];
    row_delta_[r] = 0;
    row_touched_[r] = 0;
    if (!ok || d == 0 || !rows_.active(r)) continue;
    const int64_t slack = rows_.slack(r);
    if (slack + d < 0) {
      ok = false;
    } else if (d < 0) {
      *t_max = std::min(*t_max, slack / -d);
    }
  }
  return ok;
}

void IntegerSheetPump::Apply(const Step& step) {
  const IntegerSheet& sheet = step.sheet;
  quantization_.Apply(sheet, step.t);
  SheetSubproblem& group = GroupOf(sheet.bundles[0]);
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    rows_.OnBundleMoved(sheet.bundles[i], step.t * sheet.deltas[i]);
    group.MarkBundleMoved(sheet.bundles[i]);
  }
  switch (SignOfSheet(sheet)) {
    case SheetSign::kInflating:
      ++stats_.sheets_inflating;
      break;
    case SheetSign::kDeflating:
      ++stats_.sheets_deflating;
      break;
    case SheetSign::kMixed:
      ++stats_.sheets_mixed;
      break;
  }
  ++accepted_sheets_;
  changed_since_search_ = true;
  search_clean_ = false;
}

// ---------------------------------------------------------------------------------------------
// Greedy descent (Alg. 1, inner loop; Alg. 2 per root)

void IntegerSheetPump::PushRoot(BundleId b) {
  ++stamp_[b];
  heap_.push({std::abs(quantization_.mean_deviation(b)), b, stamp_[b]});
}

void IntegerSheetPump::RecordDependencies(BundleId root, std::span<const BundleId> support) {
  const int32_t stamp = stamp_[root];
  if (!support.empty()) {
    for (BundleId c : support) users_[c].push_back({root, stamp});
    return;
  }
  // No sheet (infeasible LP): what could change that is the slack of the rows around the root.
  users_[root].push_back({root, stamp});
  for (const InequalityRows::Incidence& inc : rows_.rows_of_bundle(root)) {
    if (!rows_.active(inc.row)) continue;
    for (const LinearTerm& t : rows_.terms(inc.row)) users_[t.var].push_back({root, stamp});
  }
}

void IntegerSheetPump::InvalidateAfter(const IntegerSheet& sheet) {
  // Bundles whose value changed, plus those sharing a row with them (whose rows' slack changed):
  // every root whose last sheet went through one of them may now find a different sheet.
  ++mark_epoch_;
  std::vector<BundleId> affected;
  auto mark = [&](BundleId b) {
    if (bundle_mark_[b] != mark_epoch_) {
      bundle_mark_[b] = mark_epoch_;
      affected.push_back(b);
    }
  };
  for (BundleId b : sheet.bundles) {
    mark(b);
    for (const InequalityRows::Incidence& inc : rows_.rows_of_bundle(b)) {
      if (!rows_.active(inc.row)) continue;
      for (const LinearTerm& t : rows_.terms(inc.row)) mark(t.var);
    }
  }
  ++mark_epoch_;
  for (BundleId c : affected) {
    for (const auto& [root, stamp] : users_[c]) {
      if (stamp_[root] == stamp && bundle_mark_[root] != mark_epoch_) {
        bundle_mark_[root] = mark_epoch_;
        PushRoot(root);
      }
    }
    users_[c].clear();
  }
  for (BundleId b : sheet.bundles) {
    if (bundle_mark_[b] != mark_epoch_) {
      bundle_mark_[b] = mark_epoch_;
      PushRoot(b);
    }
  }
}

absl::StatusOr<bool> IntegerSheetPump::Greedy(bool thorough, QuantizationPhase phase) {
  ScopedSeconds timer(&stats_.greedy_seconds);
  const int nb = bundles_.num_bundles();
  stamp_.assign(nb, 0);
  users_.resize(nb);
  for (auto& list : users_) list.clear();
  heap_ = {};
  for (BundleId b = 0; b < nb; ++b) PushRoot(b);
  const double skip_limit = std::max(tuning_.skip_fraction * nb, double{1} * tuning_.min_skip);

  bool changed = false;
  bool pass_changed = false;
  int64_t skipped = 0;
  while (true) {
    if (heap_.empty() || (!thorough && static_cast<double>(skipped) >= skip_limit)) {
      if (thorough || !tuning_.repeat_greedy_passes || !pass_changed) break;
      // Alg. 1's outer "while still improving": a fresh pass over every root.
      pass_changed = false;
      skipped = 0;
      heap_ = {};
      for (auto& list : users_) list.clear();
      for (BundleId b = 0; b < nb; ++b) PushRoot(b);
    }
    const RootEntry top = heap_.top();
    heap_.pop();
    const BundleId b = top.bundle;
    if (top.stamp != stamp_[b]) continue;
    // Alg. 2: pump the root toward its target; a thorough pass also tries the other way.
    const bool toward_inflation = quantization_.mean_deviation(b) >= 0;
    bool accepted = false;
    for (int k = 0; k < (thorough ? 2 : 1) && !accepted; ++k) {
      const bool inflate = (k == 0) == toward_inflation;
      SheetRequest request;
      request.root = b;
      request.inflate_root = inflate;
      request.allow_inflation = options_.mixed_sign || inflate;
      request.allow_deflation = options_.mixed_sign || !inflate;
      absl::StatusOr<bool> found = ComputeStep(GroupOf(b), request, &step_);
      if (!found.ok()) return found.status();
      if (stop_) return changed;
      RecordDependencies(
          b, *found ? std::span<const BundleId>(step_.sheet.bundles) : std::span<const BundleId>());
      const int repairs = thorough || tuning_.repair_in_greedy ? tuning_.repair_attempts : 0;
      blocked_.clear();
      for (int attempt = 0; attempt < repairs && *found && step_.gain >= -Tolerance(); ++attempt) {
        // Steer the LP around the bundles this sheet made worse.
        const size_t before = blocked_.size();
        for (size_t i = 0; i < step_.sheet.bundles.size(); ++i) {
          const BundleId c = step_.sheet.bundles[i];
          const int64_t delta = step_.t * step_.sheet.deltas[i];
          if (c != b && quantization_.MoveChange(c, delta) > 0) blocked_.push_back({c, delta > 0});
        }
        if (blocked_.size() == before) break;
        request.blocked = blocked_;
        found = ComputeStep(GroupOf(b), request, &step_);
        if (!found.ok()) return found.status();
        if (stop_) return changed;
      }
      if (*found && step_.gain < -Tolerance()) {
        Apply(step_);
        accepted = true;
      }
    }
    if (!accepted) {
      ++skipped;
      continue;
    }
    skipped = 0;
    changed = pass_changed = true;
    Report(phase);
    InvalidateAfter(step_.sheet);
  }
  return changed;
}

// ---------------------------------------------------------------------------------------------
// Separating updates (Alg. 3 and App. B)

absl::StatusOr<bool> IntegerSheetPump::SeparatingUpdate() {
  ScopedSeconds timer(&stats_.separating_update_seconds);
  bool changed = false;
  // One solve per subproblem satisfies all its rows at once; a second sweep only runs when a
  // scaled sheet was rejected somewhere and a fallback mode took over.
  for (int sweep = 0; sweep < 3 && rows_.num_violated_active() > 0; ++sweep) {
    std::vector<int32_t> violated_groups;
    for (int32_t r = 0; r < rows_.size(); ++r) {
      if (rows_.active(r) && rows_.violated(r)) {
        violated_groups.push_back(group_of_bundle_[rows_.terms(r)[0].var]);
      }
    }
    std::sort(violated_groups.begin(), violated_groups.end());
    violated_groups.erase(std::unique(violated_groups.begin(), violated_groups.end()),
                          violated_groups.end());
    bool progress = false;
    for (int32_t g : violated_groups) {
      absl::StatusOr<bool> done =
          tuning_.failsafe_separation_only ? absl::StatusOr<bool>(false) : SeparateGroup(g);
      if (done.ok() && !*done && !stop_) done = FailsafeGroup(g);
      if (!done.ok()) return done.status();
      if (stop_) return changed;
      progress |= *done;
    }
    changed |= progress;
    if (!progress) break;
  }
  return changed;
}

absl::StatusOr<bool> IntegerSheetPump::SeparateGroup(int32_t g) {
  // Default mode (deflation allowed), then the non-deflating mode (7g). Without mixed-sign
  // sheets only the uniform-sign (non-deflating) mode is used.
  for (const bool allow_deflation : {true, false}) {
    if (allow_deflation && !options_.mixed_sign) continue;
    SheetRequest request;
    request.allow_deflation = allow_deflation;
    if (tuning_.marginal_separation_weights) request.weights = WeightScheme::kMarginalCost;
    absl::StatusOr<bool> found = ComputeStep(*groups_[g], request, &step_);
    if (!found.ok()) return found.status();
    if (*found) {
      Apply(step_);
      ++stats_.separating_updates;
      Report(QuantizationPhase::kSeparation);
      return true;
    }
  }
  return false;
}

absl::StatusOr<bool> IntegerSheetPump::FailsafeGroup(int32_t g) {
  // App. B: swap the structural rows of this subproblem for their non-negative forms B+ and
  // solve non-deflating; every multiple of such a sheet stays feasible.
  SheetSubproblem& group = *groups_[g];
  std::vector<std::pair<int32_t, int32_t>> swapped;
  std::vector<int32_t> to_attach;
  const std::vector<int32_t> group_rows = group.rows();
  for (int32_t r : group_rows) {
    if (!is_default_[r] || required_[r] || !rows_.active(r)) continue;
    const int32_t f = failsafe_of_[r];
    if (f == kNoId || f == r) continue;
    rows_.SetActive(r, false);
    group.MarkRowChanged(r);
    if (!rows_.active(f)) {
      rows_.SetActive(f, true);
      if (context_.lp_row_of_row[f] == kNoId) {
        to_attach.push_back(f);
      } else {
        group.MarkRowChanged(f);
      }
    }
    swapped.push_back({r, f});
  }
  group.AddRows(to_attach);

  SheetRequest request;
  request.allow_deflation = false;
  absl::StatusOr<bool> found = ComputeStep(group, request, &step_);
  if (found.ok() && *found) {
    Apply(step_);
    ++stats_.failsafe_updates;
    Report(QuantizationPhase::kFailsafe);
  }

  // Default rows that hold at the new q come back; the others stay replaced by their B+ form,
  // which is an equally sufficient separation condition for the same path.
  for (const auto& [r, f] : swapped) {
    if (!rows_.violated(r)) {
      rows_.SetActive(r, true);
      group.MarkRowChanged(r);
    }
  }
  for (const auto& swap : swapped) {
    const int32_t f = swap.second;
    if (is_default_[f] || required_[f]) continue;
    const bool still_needed = std::any_of(swapped.begin(), swapped.end(), [&](const auto& pair) {
      return pair.second == f && !rows_.active(pair.first);
    });
    if (!still_needed && rows_.active(f)) {
      rows_.SetActive(f, false);
      group.MarkRowChanged(f);
    }
  }
  if (!found.ok()) return found.status();
  return *found;
}

// ---------------------------------------------------------------------------------------------
// Separation rows

bool IntegerSheetPump::AnySimpleRowViolated() const {
  const std::span<const int64_t> x = quantization_.values();
  for (int i = 0; i < simple_terms_.size(); ++i) {
    int64_t value = 0;
    for (const LinearTerm& t : simple_terms_[i]) value += t.coef * x[t.var];
    if (value < simple_rhs_[i]) return true;
  }
  return false;
}

std::vector<int32_t> IntegerSheetPump::ActivateSimpleRows() {
  // All or nothing (separation.md section 2.5): once any simple row is violated, all of them
  // join the active rows for the rest of the run.
  simple_active_ = true;
  std::vector<int32_t> added;
  for (int i = 0; i < simple_terms_.size(); ++i) {
    const int32_t r = rows_.Find(simple_terms_[i], simple_rhs_[i]);
    if (r == kNoId) {
      added.push_back(AddRow(simple_terms_[i], simple_rhs_[i], RowOrigin::kSimple, true));
      continue;
    }
    required_[r] = 1;
    if (!rows_.active(r)) {
      rows_.SetActive(r, true);
      if (context_.lp_row_of_row[r] == kNoId) {
        added.push_back(r);
      } else {
        GroupOf(rows_.terms(r)[0].var).MarkRowChanged(r);
      }
    }
  }
  return added;
}

absl::StatusOr<int64_t> IntegerSheetPump::SearchRound(std::vector<int32_t>* new_rows) {
  std::vector<SeparationViolation> violations;
  {
    ScopedSeconds timer(&stats_.separation_search_seconds);
    quantization_.ArcValues(&arc_values_);
    violations = separation_->FindFirstViolations(arc_values_);
  }
  ++stats_.separation_rounds;
  changed_since_search_ = false;
  std::vector<LinearTerm> default_terms, failsafe_terms;
  for (const SeparationViolation& v : violations) {
    failsafe_terms = bundles_.ToBundleTerms(v.failsafe_row.terms);
    default_terms = bundles_.ToBundleTerms(v.default_row.terms);
    int64_t default_rhs = v.default_row.rhs;
    if (failsafe_terms.empty()) continue;  // cannot happen for +1 rows with terms
    // A default row whose mixed terms cancel within a bundle can never hold: use B+ for it.
    if (default_terms.empty()) {
      default_terms = failsafe_terms;
      default_rhs = v.failsafe_row.rhs;
    }
    int32_t r = rows_.Find(default_terms, default_rhs);
    if (r == kNoId) {
      r = AddRow(default_terms, default_rhs, RowOrigin::kStructural, true);
      new_rows->push_back(r);
      ++stats_.separation_rows;
    } else if (!rows_.active(r)) {
      rows_.SetActive(r, true);
      if (context_.lp_row_of_row[r] == kNoId) {
        new_rows->push_back(r);
      } else {
        GroupOf(default_terms[0].var).MarkRowChanged(r);
      }
      ++stats_.separation_rows;
    }
    is_default_[r] = 1;
    if (failsafe_of_[r] == kNoId) {
      int32_t f = rows_.Find(failsafe_terms, v.failsafe_row.rhs);
      if (f == kNoId) f = AddRow(failsafe_terms, v.failsafe_row.rhs, RowOrigin::kFailsafe, false);
      failsafe_of_[r] = f;
    }
  }
  return static_cast<int64_t>(violations.size());
}

void IntegerSheetPump::AttachRows(const std::vector<int32_t>& new_rows) {
  if (new_rows.empty()) return;
  // Rows spanning several subproblems merge them (section 4.4 is a static decomposition; the
  // separation rows can couple it); only the merged subproblem's LP is rebuilt.
  DisjointSets sets(static_cast<int>(groups_.size()));
  for (int32_t r : new_rows) {
    const std::span<const LinearTerm> terms = rows_.terms(r);
    for (const LinearTerm& t : terms)
      sets.Join(group_of_bundle_[terms[0].var], group_of_bundle_[t.var]);
  }
  std::vector<std::vector<int32_t>> rows_by_root(groups_.size());
  for (int32_t r : new_rows) {
    rows_by_root[sets.Find(group_of_bundle_[rows_.terms(r)[0].var])].push_back(r);
  }
  std::vector<std::vector<int32_t>> members(groups_.size());
  for (int32_t g = 0; g < static_cast<int32_t>(groups_.size()); ++g) {
    if (groups_[g] != nullptr) members[sets.Find(g)].push_back(g);
  }
  const int32_t num_groups = static_cast<int32_t>(groups_.size());
  for (int32_t root = 0; root < num_groups; ++root) {
    if (rows_by_root[root].empty()) continue;
    if (members[root].size() == 1) {
      groups_[root]->AddRows(rows_by_root[root]);
      continue;
    }
    std::vector<BundleId> bundles;
    std::vector<int32_t> equalities, rows;
    for (int32_t g : members[root]) {
      const SheetSubproblem& old = *groups_[g];
      bundles.insert(bundles.end(), old.bundles().begin(), old.bundles().end());
      equalities.insert(equalities.end(), old.equalities().begin(), old.equalities().end());
      rows.insert(rows.end(), old.rows().begin(), old.rows().end());
    }
    rows.insert(rows.end(), rows_by_root[root].begin(), rows_by_root[root].end());
    std::sort(bundles.begin(), bundles.end());
    const int32_t merged = static_cast<int32_t>(groups_.size());
    for (BundleId b : bundles) group_of_bundle_[b] = merged;
    for (int32_t g : members[root]) groups_[g].reset();
    groups_.push_back(std::make_unique<SheetSubproblem>(&context_, std::move(bundles),
                                                        std::move(equalities), std::move(rows)));
  }
}

// ---------------------------------------------------------------------------------------------
// Reporting

void IntegerSheetPump::Report(QuantizationPhase phase) {
  if (observer_ == nullptr) return;
  ProgressEvent event;
  event.phase = phase;
  event.iteration = accepted_sheets_;
  event.separation_round = stats_.separation_rounds;
  event.objective = quantization_.objective();
  event.violated_constraints = rows_.num_violated_active();
  if (!simple_active_) {
    const std::span<const int64_t> x = quantization_.values();
    for (int i = 0; i < simple_terms_.size(); ++i) {
      int64_t value = 0;
      for (const LinearTerm& t : simple_terms_[i]) value += t.coef * x[t.var];
      if (value < simple_rhs_[i]) ++event.violated_constraints;
    }
  }
  event.separating = search_clean_;
  event.elapsed_seconds = SecondsSince(start_);
  if (observer_->WantsQuantization()) {
    quantization_.ArcValues(&arc_values_);
    event.q = arc_values_;
  }
  observer_->OnProgress(event);
}

void IntegerSheetPump::SaveIfBestValid() {
  const double objective = quantization_.objective();
  if (has_valid_ && objective >= best_valid_objective_) return;
  has_valid_ = true;
  best_valid_objective_ = objective;
  best_valid_values_.assign(quantization_.values().begin(), quantization_.values().end());
}

IspOutcome IntegerSheetPump::Finish() {
  IspOutcome outcome;
  outcome.termination = stop_ ? termination_ : Termination::kConverged;
  // The best q that passed a search: usually the last one, but a separating update after a
  // thorough pass can end in a worse valid state than an earlier one.
  if (has_valid_) quantization_.SetValues(best_valid_values_);
  outcome.separating = has_valid_;
  outcome.q = quantization_.ArcValues();
  stats_.subproblems = static_cast<int32_t>(
      std::count_if(groups_.begin(), groups_.end(), [](const auto& g) { return g != nullptr; }));
  stats_.solve_seconds = SecondsSince(start_);
  outcome.stats = stats_;
  return outcome;
}

// ---------------------------------------------------------------------------------------------
// Alg. 1 with the lazy separation loop of separation.md section 3.13

absl::StatusOr<IspOutcome> IntegerSheetPump::Run() {
  components_.emplace(mesh_, consistency_, bundles_);
  context_.has_floor.assign(bundles_.num_bundles(), 0);
  BuildEqualities();
  BuildInitialRows();
  BuildSubproblems();
  separation_.emplace(mesh_, options_.separation);
  bundle_mark_.assign(bundles_.num_bundles(), 0);

  // The first descent runs with consistency and C rows only.
  absl::StatusOr<bool> greedy = Greedy(false, QuantizationPhase::kGreedy);
  if (!greedy.ok()) return greedy.status();

  for (int round = 0; round < tuning_.max_separation_rounds && !ShouldStop(); ++round) {
    std::vector<int32_t> new_rows;
    int64_t found = 0;
    if (!simple_active_ && AnySimpleRowViolated()) {
      new_rows = ActivateSimpleRows();
    } else if (rows_.num_violated_active() == 0 && changed_since_search_) {
      absl::StatusOr<int64_t> searched = SearchRound(&new_rows);
      if (!searched.ok()) return searched.status();
      found = *searched;
      if (found == 0) {
        search_clean_ = true;
        SaveIfBestValid();
      }
      Report(QuantizationPhase::kSeparation);
    }
    AttachRows(new_rows);

    if (rows_.num_violated_active() > 0) {
      absl::StatusOr<bool> separated = SeparatingUpdate();
      if (!separated.ok()) return separated.status();
      if (!*separated && new_rows.empty()) break;  // stuck: nothing new and nothing fixable
      greedy = Greedy(false, QuantizationPhase::kGreedy);
      if (!greedy.ok()) return greedy.status();
      continue;
    }
    // Violations reported, but all of them rows that already hold: no way forward.
    if (found > 0 || !search_clean_) break;
    if (!tuning_.thorough_final_pass) break;
    greedy = Greedy(true, QuantizationPhase::kFinal);
    if (!greedy.ok()) return greedy.status();
    if (!*greedy) break;
  }
  return Finish();
}

}  // namespace

absl::StatusOr<IspOutcome> RunIntegerSheetPump(const TMesh& mesh, const QuantizeOptions& options,
                                               const IspTuning& tuning, ProgressObserver* observer,
                                               const SolveInterrupter* interrupter) {
  IntegerSheetPump pump(mesh, options, tuning, observer, interrupter);
  return pump.Run();
}

}  // namespace ispq
