// SPDX-License-Identifier: Apache-2.0
#include "core/isp/integer_sheet_pump.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <utility>

#include "core/arc_bundles.h"
#include "core/bundle_potentials.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/greedy_queue.h"
#include "core/isp/layered_start.h"
#include "core/isp/separation_rows.h"
#include "core/isp/sheet_coverage.h"
#include "core/isp/sheet_step.h"
#include "core/isp/subproblem_set.h"
#include "core/run_clock.h"
#include "core/separation_check.h"
#include "core/status_macros.h"
#include "core/subproblems.h"

namespace ispq {
namespace {

// A request for the bulk descent's LP (SheetRequest::unit_moves) in the given directions; in a
// thorough pass the LP confirms a flow that finds no step (SheetRequest::confirm_stalled_flow).
SheetRequest UnitMoves(bool allow_inflation, bool allow_deflation, bool thorough) {
  SheetRequest request;
  request.unit_moves = true;
  request.confirm_stalled_flow = thorough;
  request.weights = WeightScheme::kUnitCost;
  request.allow_inflation = allow_inflation;
  request.allow_deflation = allow_deflation;
  return request;
}

// The engine's LPs, each stopping mid-solve once the run's clock says so: one sheet LP over a
// million-arc part can run for many times the time limit.
SheetLpFactory StoppedByClock(const SheetLpFactory& new_lp, RunClock& clock) {
  return [new_lp, &clock](int num_columns) {
    std::unique_ptr<SheetLp> lp = new_lp(num_columns);
    lp->SetStopCheck([&clock] { return clock.ShouldStop(); });
    return lp;
  };
}

// A greedy pass (not a thorough one) ends after this many consecutive roots without an
// improving sheet: max(kSkipFraction * bundles, kMinSkip). A pass that has improved nothing yet
// ends sooner, after kIdleSkipBase + kIdleSkipFraction * bundles roots (if that is less): at a
// coarse level the first descent of a large part finds nothing to improve (q = 0 is all but
// optimal before separation) and its checks were a tenth of the run before the first valid q
// (the thorough pass checks every root again anyway). Passes that improve keep the full limit:
// ending them as soon made the final thorough pass do the descent, 2.5x slower at 100k arcs.
constexpr double kSkipFraction = 0.5;
constexpr int kMinSkip = 30;
constexpr double kIdleSkipBase = 128;
constexpr double kIdleSkipFraction = 0.05;
// Safety nets against a separation loop that stops making progress: rounds that end in a greedy
// descent, and searches repeated right after a separating update because rows were left over.
constexpr int kMaxSeparationRounds = 500;
constexpr int kMaxRepeatedSearches = 5000;

// The mesh's structures (consistency rows, bundles, separation check) and the clock belong to
// RunIntegerSheetPump, which builds them first so that the layered start can use them before the
// engine builds its LPs; `start` is that start's q if it was valid.
class IntegerSheetPump {
 public:
  IntegerSheetPump(const TMesh& mesh, const QuantizeOptions& options, const SheetLpFactory& new_lp,
                   const IspTuning& tuning, ProgressObserver* observer, RunClock& clock,
                   const ConsistencyMatrix& consistency, const ArcBundles& bundles,
                   BundleQuantization quantization, SeparationCheck& separation,
                   const QuantizeStats& stats, std::optional<ValidStart> start)
      : options_(options),
        tuning_(tuning),
        observer_(observer),
        clock_(clock),
        stats_(stats),
        consistency_(consistency),
        bundles_(bundles),
        quantization_(std::move(quantization)),
        initial_subproblems_(mesh, consistency_, bundles_),
        rows_(mesh, bundles_, quantization_, options.per_arc_nonnegative),
        subproblems_(consistency_, bundles_, initial_subproblems_, quantization_, rows_.store(),
                     rows_.Floors(), mesh.num_arcs(), StoppedByClock(new_lp, clock),
                     options.decompose),
        separation_(separation),
        steps_(quantization_, rows_.store(), tuning, clock_, stats_),
        queue_(quantization_, rows_.store()),
        thorough_queue_(quantization_, rows_.store()),
        coverage_(quantization_.num_bundles()) {
    if (tuning.bulk_descent_as_flow && bundles_.num_bundles() >= tuning.bulk_descent_min_bundles) {
      potentials_ = BundlePotentials::Compute(mesh, consistency_, bundles_);
      if (potentials_.has_value()) {
        subproblems_.UseFlows(&*potentials_, static_cast<size_t>(tuning.bulk_descent_min_bundles),
                              [&clock] { return clock.ShouldStop(); });
      }
    }
    if (start.has_value()) {
      has_valid_ = true;
      best_valid_objective_ = start->objective;
      best_valid_values_ = std::move(start->values);
    }
  }

  absl::StatusOr<IspOutcome> Run();

 private:
  // Greedy descent (Alg. 1, inner loop): pumps roots until the pass converges; true if a sheet
  // was accepted.
  absl::StatusOr<bool> Greedy(bool thorough, QuantizationPhase phase);
  // Alg. 2 for one root: toward its target (and, in a thorough pass on a subproblem below
  // IspTuning::away_checks_max_bundles, the other way); true if a sheet was accepted.
  absl::StatusOr<bool> PumpRoot(BundleId root, bool thorough);
  // The greedy pass of the subproblems that descend in bulk (IspTuning::bulk_descent_min_bundles):
  // the best combination of unit moves, applied until none improves; true if one was. In a
  // thorough pass, none improves by the LP's word too.
  absl::StatusOr<bool> BulkDescent(bool thorough, QuantizationPhase phase);
  bool DescendsInBulk(const SheetSubproblem& subproblem) const {
    return subproblem.bundles().size() >= static_cast<size_t>(tuning_.bulk_descent_min_bundles);
  }
  // The cheapest sheet of a root is often not an improving one while an improving one exists:
  // blocks the bundles it made worse from moving that way and solves again.
  absl::StatusOr<bool> SteerAroundWorsenedBundles(BundleId root, SheetRequest& request, bool found);
  void Apply(const SheetStep& step);
  // The arcs a step moves, each counted once per unit.
  double MovedArcs(const SheetStep& step) const;
  GreedyQueue& QueueOf(bool thorough) { return thorough ? thorough_queue_ : queue_; }
  // Rows joined the active rows: the roots whose last sheet crossed them are pumped again.
  void RequeueUsersOfRows(std::span<const int32_t> new_rows);
  double Tolerance() const { return quantization_.GainTolerance(); }

  // Separating updates (Alg. 3, App. B): one solve per subproblem with violated rows.
  absl::StatusOr<bool> SeparatingUpdate();
  absl::StatusOr<bool> SeparateSubproblem(int32_t id);
  // Finds the step `request` asks for in subproblem `id` and applies it as a separating update;
  // true if there was one.
  absl::StatusOr<bool> ApplySeparatingStep(int32_t id, const SheetRequest& request);
  absl::StatusOr<bool> FailsafeSubproblem(int32_t id);
  // One lazy separation round on the current q: activates the rows of at most
  // tuning_.max_new_rows_per_search violations per subproblem and sets rows_left_over_ if more
  // were found; returns the number of violations found (0 iff q passed the search).
  int64_t SearchRound(std::vector<int32_t>* new_rows);
  // The lazy separation search on the current q (timed as the search phase), handing the
  // violations to `sink` until it returns false; returns how many it handed over.
  int64_t FindViolations(const std::function<bool(const SeparationViolation&)>& sink);
  // Anytime: whether the q a separating update left is separating already, reported at once if
  // so. What the probe finds is not enforced (the search after the next descent does that), so
  // the run takes the same path with or without it; only the first valid q comes earlier.
  void ProbeSeparation();

  void Report(QuantizationPhase phase);
  void SaveIfBestValid();
  // Whether the current q, if separating, would be the best valid q so far.
  bool CurrentWouldBeBestValid() const {
    return !has_valid_ || quantization_.objective() < best_valid_objective_;
  }
  IspOutcome Finish();

  const QuantizeOptions& options_;
  const IspTuning& tuning_;
  ProgressObserver* observer_;
  RunClock& clock_;
  QuantizeStats stats_;

  const ConsistencyMatrix& consistency_;
  const ArcBundles& bundles_;
  BundleQuantization quantization_;
  const Subproblems initial_subproblems_;       // before separation rows couple any
  std::optional<BundlePotentials> potentials_;  // for the flows of the LPs without a root
  SeparationRows rows_;
  SubproblemSet subproblems_;
  SeparationCheck& separation_;
  SheetStepFinder steps_;
  // The roots of ordinary and of thorough passes: each pass goes on from what changed since the
  // last pass of its kind (core/isp/greedy_queue.h).
  GreedyQueue queue_;
  GreedyQueue thorough_queue_;
  // The greedy checks on large subproblems that a non-improving sheet answered.
  SheetCoverage coverage_;

  SheetStep step_;
  std::vector<std::pair<BundleId, bool>> blocked_;
  std::vector<int64_t> arc_values_;

  bool changed_since_search_ = true;
  bool rows_left_over_ = false;  // the last search found violations whose rows were not activated
  bool search_clean_ = false;    // the current q passed the simple rows and a search
  int64_t accepted_sheets_ = 0;
  bool has_valid_ = false;
  double best_valid_objective_ = 0;
  std::vector<int64_t> best_valid_values_;
};

// ---------------------------------------------------------------------------------------------
// Alg. 1 with the lazy separation loop (core/README.md, section The separation loop)

absl::StatusOr<IspOutcome> IntegerSheetPump::Run() {
  // From a separating start the simple rows hold: they are enforced from the first descent on.
  if (has_valid_ && tuning_.descend_from_layered_start) {
    const std::vector<int32_t> simple = rows_.ActivateSimpleRows(subproblems_);
    subproblems_.Attach(simple);
    search_clean_ = true;
  }
  // The first descent runs with consistency and C rows only.
  ISPQ_RETURN_IF_ERROR(Greedy(false, QuantizationPhase::kGreedy).status());
  int rounds = 0, repeated_searches = 0;
  while (rounds < kMaxSeparationRounds && repeated_searches < kMaxRepeatedSearches &&
         !clock_.ShouldStop()) {
    std::vector<int32_t> new_rows;
    int64_t found = 0;
    rows_left_over_ = false;
    if (!rows_.simple_rows_active() && rows_.AnyHeldSimpleRowViolated()) {
      new_rows = rows_.ActivateSimpleRows(subproblems_);
    } else if (rows_.store().num_violated_active() == 0 && changed_since_search_) {
      found = SearchRound(&new_rows);
      if (found == 0) {
        search_clean_ = true;
        SaveIfBestValid();
      }
      Report(QuantizationPhase::kSeparation);
    }
    subproblems_.Attach(new_rows);
    RequeueUsersOfRows(new_rows);

    if (rows_.store().num_violated_active() > 0) {
      ISPQ_ASSIGN_OR_RETURN(const bool separated, SeparatingUpdate());
      if (!separated && new_rows.empty()) break;  // stuck: nothing new and nothing fixable
      // The update often separates what the left-over violations were about, by another path
      // than the one their rows name: search again before descending, so those rows are only
      // enforced if the violations persist.
      if (separated && rows_left_over_ && rows_.store().num_violated_active() == 0) {
        ++repeated_searches;
        continue;
      }
      if (separated) ProbeSeparation();
      ISPQ_RETURN_IF_ERROR(Greedy(false, QuantizationPhase::kGreedy).status());
      ++rounds;
      continue;
    }
    // Violations reported, but all of them rows that already hold: no way forward.
    if (found > 0 || !search_clean_ || !tuning_.thorough_final_pass) break;
    ISPQ_ASSIGN_OR_RETURN(const bool improved, Greedy(true, QuantizationPhase::kFinal));
    if (!improved) break;
    ++rounds;
  }
  return Finish();
}

// ---------------------------------------------------------------------------------------------
// Greedy descent (Alg. 1, inner loop; Alg. 2 per root)

absl::StatusOr<bool> IntegerSheetPump::Greedy(bool thorough, QuantizationPhase phase) {
  ScopedCpuSeconds timer(&stats_.greedy_seconds);
  GreedyQueue& queue = QueueOf(thorough);
  if (!queue.started()) queue.Reset();
  const double bundles = quantization_.num_bundles();
  const double skip_limit = std::max(kSkipFraction * bundles, double{1} * kMinSkip);
  const double idle_skip_limit = std::min(skip_limit, kIdleSkipBase + kIdleSkipFraction * bundles);
  ISPQ_ASSIGN_OR_RETURN(bool changed, BulkDescent(thorough, phase));
  if (clock_.stopped()) return changed;
  int64_t skipped = 0;
  // One pass: the queue holds the roots that every sheet applied since they were last pumped (in
  // this pass or before it) affects, so when it runs dry (or a non-thorough pass meets its skip
  // limit of unproductive roots in a row) the pass has converged. The first pass of each kind
  // pumps all.
  while (thorough || static_cast<double>(skipped) < (changed ? skip_limit : idle_skip_limit)) {
    const std::optional<BundleId> root = queue.Pop();
    if (!root.has_value()) break;
    if (DescendsInBulk(subproblems_.Of(*root))) continue;  // BulkDescent answered for it
    ISPQ_ASSIGN_OR_RETURN(const bool accepted, PumpRoot(*root, thorough));
    if (clock_.stopped()) return changed;
    if (!accepted) {
      ++skipped;
      // Anytime: a pass that improved and has then been idle as long as an idle pass may be is
      // most likely converged; the rest of its stretch only confirms it. Unless a valid q at
      // least as good is known, probe this one now instead of after the stretch (on the 100k-arc
      // part at level 5 the stretch was 600 of the first descent's 1343 LP solves).
      if (CurrentWouldBeBestValid() && changed && !thorough && idle_skip_limit < skip_limit &&
          static_cast<double>(skipped) == std::ceil(idle_skip_limit)) {
        ProbeSeparation();
      }
      continue;
    }
    skipped = 0;
    changed = true;
    Report(phase);
  }
  return changed;
}

absl::StatusOr<bool> IntegerSheetPump::PumpRoot(BundleId root, bool thorough) {
  const bool toward_inflation = quantization_.mean_deviation(root) >= 0;
  const size_t size = subproblems_.Of(root).bundles().size();
  const bool covering = size >= static_cast<size_t>(tuning_.cover_min_bundles);
  const bool both_ways = thorough && size < static_cast<size_t>(tuning_.away_checks_max_bundles);
  for (int k = 0; k < (both_ways ? 2 : 1); ++k) {
    const bool inflate = (k == 0) == toward_inflation;
    if (covering) {
      const std::optional<SheetCoverage::Answer> answer = coverage_.CoveringSheet(root, inflate);
      if (answer.has_value()) {
        // The root is pumped again when a bundle of the covering sheet moves.
        QueueOf(thorough).RecordDependencies(root, answer->bundles, answer->id);
        ++stats_.covered_checks;
        continue;
      }
    }
    SheetRequest request;
    request.root = root;
    request.inflate_root = inflate;
    request.allow_inflation = options_.mixed_sign || inflate;
    request.allow_deflation = options_.mixed_sign || !inflate;
    ISPQ_ASSIGN_OR_RETURN(bool found, steps_.Find(subproblems_.Of(root), request, &step_));
    if (clock_.stopped()) return false;
    QueueOf(thorough).RecordDependencies(
        root, found ? std::span<const BundleId>(step_.sheet.bundles) : std::span<const BundleId>());
    if (covering && found && step_.gain >= -Tolerance()) coverage_.Cover(step_.sheet);
    if (thorough &&
        (!covering || !found || step_.gain <= tuning_.repair_max_loss_per_arc * MovedArcs(step_))) {
      ISPQ_ASSIGN_OR_RETURN(found, SteerAroundWorsenedBundles(root, request, found));
      if (clock_.stopped()) return false;
    }
    if (found && step_.gain < -Tolerance()) {
      Apply(step_);
      return true;
    }
  }
  return false;
}

absl::StatusOr<bool> IntegerSheetPump::BulkDescent(bool thorough, QuantizationPhase phase) {
  bool changed = false;
  for (const int32_t id : subproblems_.Ids()) {
    SheetSubproblem& subproblem = subproblems_.at(id);
    if (!DescendsInBulk(subproblem)) continue;
    // Without mixed-sign sheets, inflating and deflating combinations take turns.
    const std::vector<std::pair<bool, bool>> modes =
        options_.mixed_sign ? std::vector<std::pair<bool, bool>>{{true, true}}
                            : std::vector<std::pair<bool, bool>>{{true, false}, {false, true}};
    for (bool progress = true; progress;) {
      progress = false;
      for (const auto& [inflation, deflation] : modes) {
        while (true) {
          ISPQ_ASSIGN_OR_RETURN(
              const bool found,
              steps_.Find(subproblem, UnitMoves(inflation, deflation, thorough), &step_));
          if (clock_.stopped()) return changed;
          if (!found || step_.gain >= -Tolerance()) break;
          Apply(step_);
          changed = progress = true;
          Report(phase);
        }
      }
      if (modes.size() == 1) break;
    }
  }
  return changed;
}

absl::StatusOr<bool> IntegerSheetPump::SteerAroundWorsenedBundles(BundleId root,
                                                                  SheetRequest& request,
                                                                  bool found) {
  blocked_.clear();
  for (int attempt = 0; attempt < tuning_.repair_attempts && found && step_.gain >= -Tolerance();
       ++attempt) {
    const size_t before = blocked_.size();
    for (size_t i = 0; i < step_.sheet.bundles.size(); ++i) {
      const BundleId c = step_.sheet.bundles[i];
      const int64_t delta = step_.t * step_.sheet.deltas[i];
      if (c != root && quantization_.MoveChange(c, delta) > 0) blocked_.push_back({c, delta > 0});
    }
    if (blocked_.size() == before) break;
    request.blocked = blocked_;
    ISPQ_ASSIGN_OR_RETURN(found, steps_.Find(subproblems_.Of(root), request, &step_));
    if (clock_.stopped()) return false;
  }
  return found;
}

double IntegerSheetPump::MovedArcs(const SheetStep& step) const {
  double arcs = 0;
  for (size_t i = 0; i < step.sheet.bundles.size(); ++i) {
    arcs += static_cast<double>(quantization_.arc_count(step.sheet.bundles[i])) *
            std::abs(static_cast<double>(step.t * step.sheet.deltas[i]));
  }
  return arcs;
}

void IntegerSheetPump::RequeueUsersOfRows(std::span<const int32_t> new_rows) {
  if (new_rows.empty()) return;
  coverage_.Clear();  // a covering sheet may violate the new rows
  std::vector<BundleId> bundles;
  for (int32_t r : new_rows) {
    for (const LinearTerm& t : rows_.store().terms(r)) bundles.push_back(t.var);
  }
  queue_.RequeueUsersOf(bundles);
  thorough_queue_.RequeueUsersOf(bundles);
}

void IntegerSheetPump::Apply(const SheetStep& step) {
  const IntegerSheet& sheet = step.sheet;
  quantization_.Apply(sheet, step.t);
  coverage_.Clear();
  SheetSubproblem& subproblem = subproblems_.Of(sheet.bundles[0]);
  for (size_t i = 0; i < sheet.bundles.size(); ++i) {
    rows_.OnBundleMoved(sheet.bundles[i], step.t * sheet.deltas[i]);
    subproblem.MarkBundleMoved(sheet.bundles[i]);
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
  queue_.RequeueAfter(sheet);
  thorough_queue_.RequeueAfter(sheet);
  ++accepted_sheets_;
  changed_since_search_ = true;
  search_clean_ = false;
}

// ---------------------------------------------------------------------------------------------
// Separating updates (Alg. 3 and App. B)

absl::StatusOr<bool> IntegerSheetPump::SeparatingUpdate() {
  ScopedCpuSeconds timer(&stats_.separating_update_seconds);
  bool changed = false;
  // One solve per subproblem satisfies all its rows at once; a second sweep only runs when a
  // scaled sheet was rejected somewhere and a fallback mode took over.
  for (int sweep = 0; sweep < 3 && rows_.store().num_violated_active() > 0; ++sweep) {
    bool progress = false;
    for (int32_t id : subproblems_.WithViolatedRows()) {
      absl::StatusOr<bool> done =
          tuning_.failsafe_separation_only ? absl::StatusOr<bool>(false) : SeparateSubproblem(id);
      if (done.ok() && !*done && !clock_.stopped()) done = FailsafeSubproblem(id);
      if (!done.ok()) return done.status();
      if (clock_.stopped()) return changed;
      progress |= *done;
    }
    changed |= progress;
    if (!progress) break;
  }
  return changed;
}

absl::StatusOr<bool> IntegerSheetPump::SeparateSubproblem(int32_t id) {
  // A subproblem that descends in bulk first tries the bulk LP with the violated rows in it: the
  // best combination of unit moves that satisfies them, on the LP the descent keeps warm.
  if (DescendsInBulk(subproblems_.at(id))) {
    ISPQ_ASSIGN_OR_RETURN(
        const bool applied,
        ApplySeparatingStep(id, UnitMoves(true, options_.mixed_sign, /*thorough=*/false)));
    if (applied) return true;
  }
  // Default mode (deflation allowed), then the non-deflating mode (7g). Without mixed-sign
  // sheets only the uniform-sign (non-deflating) mode is used.
  for (const bool allow_deflation : {true, false}) {
    if (allow_deflation && !options_.mixed_sign) continue;
    SheetRequest request;
    request.allow_deflation = allow_deflation;
    // A separating sheet usually moves arcs that are all in the same tier of eq. 4, where the
    // tiers hardly tell them apart: price them by their exact objective change instead.
    request.weights = WeightScheme::kMarginalCost;
    ISPQ_ASSIGN_OR_RETURN(const bool applied, ApplySeparatingStep(id, request));
    if (applied) return true;
  }
  return false;
}

absl::StatusOr<bool> IntegerSheetPump::ApplySeparatingStep(int32_t id,
                                                           const SheetRequest& request) {
  ISPQ_ASSIGN_OR_RETURN(const bool found, steps_.Find(subproblems_.at(id), request, &step_));
  if (!found) return false;
  Apply(step_);
  ++stats_.separating_updates;
  Report(QuantizationPhase::kSeparation);
  return true;
}

absl::StatusOr<bool> IntegerSheetPump::FailsafeSubproblem(int32_t id) {
  // App. B: the structural rows in their non-negative forms B+, solved non-deflating; every
  // multiple of such a sheet stays feasible.
  const std::vector<SeparationRows::Swap> swaps = rows_.UseFailsafeForms(id, subproblems_);
  SheetRequest request;
  request.allow_deflation = false;
  absl::StatusOr<bool> found = steps_.Find(subproblems_.at(id), request, &step_);
  if (found.ok() && *found) {
    Apply(step_);
    ++stats_.failsafe_updates;
    Report(QuantizationPhase::kFailsafe);
  }
  rows_.RestoreDefaultForms(swaps, subproblems_.at(id));
  return found;
}

int64_t IntegerSheetPump::SearchRound(std::vector<int32_t>* new_rows) {
  // The rows join as the search finds them; once every subproblem has its rows for this round
  // and one more was left over, the rest of the search could change nothing and is skipped.
  SeparationRows::Added added;
  const NewRowCap new_row_cap{.rows = tuning_.max_new_rows_per_search,
                              .bundles_per_extra_row = tuning_.bundles_per_extra_new_row};
  const int64_t subproblems = subproblems_.count();
  const int64_t found = FindViolations([&](const SeparationViolation& v) {
    rows_.AddViolation(v, new_row_cap, subproblems_, new_rows, &added);
    return !added.Done(subproblems);
  });
  ++stats_.separation_rounds;
  changed_since_search_ = false;
  stats_.separation_rows += added.activated;
  rows_left_over_ = added.dropped;
  return found;
}

int64_t IntegerSheetPump::FindViolations(
    const std::function<bool(const SeparationViolation&)>& sink) {
  ScopedCpuSeconds timer(&stats_.separation_search_seconds);
  quantization_.ArcValues(&arc_values_);
  return separation_.FindFirstViolations(arc_values_,
                                         [&](SeparationViolation& v) { return sink(v); });
}

void IntegerSheetPump::ProbeSeparation() {
  if (rows_.store().num_violated_active() > 0) return;
  if (!rows_.simple_rows_active() && rows_.AnyHeldSimpleRowViolated()) return;
  // Any violation answers the probe.
  if (FindViolations([](const SeparationViolation&) { return false; }) > 0) return;
  search_clean_ = true;
  changed_since_search_ = false;
  SaveIfBestValid();
  Report(QuantizationPhase::kSeparation);
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
  event.violated_constraints = rows_.NumViolated();
  event.separating = search_clean_;
  event.elapsed_seconds = clock_.ElapsedSeconds();
  event.lp_solves = stats_.lp_solves;
  if (observer_->WantsQuantization()) {
    quantization_.ArcValues(&arc_values_);
    event.q = arc_values_;
  }
  observer_->OnProgress(event);
}

void IntegerSheetPump::SaveIfBestValid() {
  if (!CurrentWouldBeBestValid()) return;
  has_valid_ = true;
  best_valid_objective_ = quantization_.objective();
  best_valid_values_.assign(quantization_.values().begin(), quantization_.values().end());
}

IspOutcome IntegerSheetPump::Finish() {
  IspOutcome outcome;
  outcome.termination = clock_.termination();
  // The best q that passed a search: usually the last one, but a separating update after a
  // thorough pass can end in a worse valid state than an earlier one.
  if (has_valid_) quantization_.SetValues(best_valid_values_);
  outcome.separating = has_valid_;
  outcome.q = quantization_.ArcValues();
  for (int32_t r : rows_.ActiveSeparationRows()) {
    outcome.separation_rows.push_back(
        {.terms = bundles_.ToArcTerms(rows_.store().terms(r)), .rhs = rows_.store().rhs(r)});
  }
  stats_.subproblems = subproblems_.count();
  stats_.solve_seconds = clock_.ElapsedSeconds();
  outcome.stats = stats_;
  return outcome;
}

}  // namespace

absl::StatusOr<IspOutcome> RunIntegerSheetPump(const TMesh& mesh, const QuantizeOptions& options,
                                               const SheetLpFactory& new_lp,
                                               const IspTuning& tuning, ProgressObserver* observer,
                                               const SolveInterrupter* interrupter) {
  RunClock clock(interrupter, options.time_limit_seconds);
  SeparationCheck separation(mesh, options.separation);
  return RunIntegerSheetPump(mesh, options, new_lp, tuning, observer, clock, separation);
}

absl::StatusOr<IspOutcome> RunIntegerSheetPump(const TMesh& mesh, const QuantizeOptions& options,
                                               const SheetLpFactory& new_lp,
                                               const IspTuning& tuning, ProgressObserver* observer,
                                               RunClock& clock, SeparationCheck& separation) {
  if (&separation.mesh() != &mesh || separation.rule() != options.separation) {
    return absl::InvalidArgumentError(
        "the separation check was built for another mesh or separation rule");
  }
  QuantizeStats stats;
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  BundleQuantization quantization(mesh, bundles, options.scaling);
  std::optional<ValidStart> start;
  if (mesh.num_arcs() >= tuning.layered_start_min_arcs) {
    start = FindLayeredStart(mesh, consistency, bundles, quantization, options.scaling, clock,
                             stats, observer);
    if (start.has_value() && tuning.descend_from_layered_start) {
      quantization.SetValues(start->values);
    }
  }
  IntegerSheetPump pump(mesh, options, new_lp, tuning, observer, clock, consistency, bundles,
                        std::move(quantization), separation, stats, std::move(start));
  return pump.Run();
}

}  // namespace ispq
