// SPDX-License-Identifier: Apache-2.0
#include "core/exact/exact_quantizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/exact/bundle_objective.h"
#include "core/exact/incumbent_checker.h"
#include "core/exact/quantization_constraints.h"
#include "core/exact/quantization_milp.h"
#include "core/status_macros.h"

namespace ispq {
namespace {

// A solution must beat the best by this much (objective units) to count as better; OPTIMAL means
// optimal within it.
constexpr double kImprovementTolerance = 1e-6;
// Progress events from inside a solve at most this often (improvements are always reported).
constexpr double kReportIntervalSeconds = 0.05;
constexpr double kNoBound = -std::numeric_limits<double>::infinity();

class ExactSearch {
 public:
  ExactSearch(const TMesh& mesh, const QuantizeOptions& options, std::span<const int64_t> start,
              MilpSolver& solver, const ExactTuning& tuning, ProgressObserver* observer,
              RunClock& clock)
      : tuning_(tuning),
        solver_(solver),
        observer_(observer),
        clock_(clock),
        consistency_(mesh),
        bundles_(mesh, consistency_),
        objectives_(mesh, bundles_, options.scaling),
        constraints_(mesh, consistency_, bundles_, options.per_arc_nonnegative),
        checker_(mesh, options.separation, objectives_, constraints_,
                 constraints_.BundleValues(start)) {}

  absl::StatusOr<ExactOutcome> Run();

  // From the solver's callbacks.
  bool OnCandidate(std::span<const int64_t> x);
  bool OnBound(double bound, int64_t nodes);

 private:
  // One MILP solve over the current rows; true if it proved that nothing satisfying them beats
  // the best valid q.
  absl::StatusOr<bool> SolveOnce();
  absl::StatusOr<MilpResult> SolveModel(const QuantizationMilp& milp);
  // The LP relaxation without separation rows: a bound for every row set the loop reaches.
  absl::StatusOr<double> RelaxationBound();
  // After a proof: if the best q violates the rows and the rows admit no q at all, the proof is
  // empty; switches to the failsafe forms (App. B) and returns true to go on.
  absl::StatusOr<bool> SwitchToFailsafeIfEmpty();

  double Cutoff() const { return checker_.best_objective() - kImprovementTolerance; }
  double CurrentBound() const { return std::min(std::max(bound_, round_bound_), Cutoff()); }
  void Report();
  ExactOutcome Finish(bool proven) const;

  const ExactTuning& tuning_;
  MilpSolver& solver_;
  ProgressObserver* observer_;
  RunClock& clock_;
  const ConsistencyMatrix consistency_;
  const ArcBundles bundles_;
  const BundleObjectives objectives_;
  QuantizationConstraints constraints_;
  IncumbentChecker checker_;

  double bound_ = kNoBound;        // proven for the rows of every earlier solve
  double round_bound_ = kNoBound;  // proven so far by the running solve
  double last_report_ = -1;
  int64_t solves_ = 0;
  int64_t nodes_ = 0;
  int64_t round_nodes_ = 0;
  int64_t round_start_rows_ = 0;
  bool used_failsafe_ = false;
  std::vector<int64_t> q_;  // scratch for progress events
};

class SolveCallbacks final : public MilpCallbacks {
 public:
  SolveCallbacks(ExactSearch& search, const QuantizationMilp& milp)
      : search_(search), milp_(milp) {}
  bool OnIncumbent(std::span<const double> columns, double) override {
    return search_.OnCandidate(milp_.BundleValuesOf(columns));
  }
  bool OnProgress(double bound, int64_t nodes) override { return search_.OnBound(bound, nodes); }

 private:
  ExactSearch& search_;
  const QuantizationMilp& milp_;
};

absl::StatusOr<ExactOutcome> ExactSearch::Run() {
  ISPQ_ASSIGN_OR_RETURN(bound_, RelaxationBound());
  Report();
  bool proven = false;
  while (!proven && solves_ < tuning_.max_solves && !clock_.ShouldStop()) {
    round_start_rows_ = checker_.rows_added();
    ISPQ_ASSIGN_OR_RETURN(proven, SolveOnce());
    if (proven) {
      ISPQ_ASSIGN_OR_RETURN(const bool go_on, SwitchToFailsafeIfEmpty());
      proven = !go_on;
      continue;
    }
    // Stopped without new rows: the time is up, or the loop cannot make progress.
    if (checker_.rows_added() == round_start_rows_) break;
  }
  if (!proven) clock_.ShouldStop();  // so that Finish can tell a passed time limit
  Report();
  return Finish(proven);
}

absl::StatusOr<bool> ExactSearch::SolveOnce() {
  ISPQ_ASSIGN_OR_RETURN(const QuantizationMilp milp,
                        BuildQuantizationMilp(objectives_, constraints_, checker_.best()));
  ISPQ_ASSIGN_OR_RETURN(const MilpResult result, SolveModel(milp));
  ++solves_;
  nodes_ += result.nodes;
  round_nodes_ = 0;
  round_bound_ = kNoBound;
  // The solver's last best may not have been reported as an incumbent.
  bool best_is_valid = true;
  if (result.best.has_value()) {
    const std::vector<int64_t> x = milp.BundleValuesOf(*result.best);
    const CandidateVerdict verdict = checker_.Check(x);
    best_is_valid = verdict != CandidateVerdict::kSeparated &&
                    verdict != CandidateVerdict::kNotFeasible &&
                    (verdict != CandidateVerdict::kSeen || constraints_.SatisfiedBy(x));
    if (verdict == CandidateVerdict::kImproved) Report();
  }
  if (result.status == MilpStatus::kStopped) {
    bound_ = std::max(bound_, result.bound);
    return false;
  }
  bound_ =
      std::max(bound_, result.status == MilpStatus::kOptimal ? result.best_objective : Cutoff());
  return best_is_valid && checker_.rows_added() == round_start_rows_;
}

absl::StatusOr<MilpResult> ExactSearch::SolveModel(const QuantizationMilp& milp) {
  MilpSolveOptions options;
  options.time_limit_seconds = clock_.RemainingSeconds();
  options.cutoff = Cutoff();
  options.absolute_gap = kImprovementTolerance / 2;
  // The best is CBC's first incumbent unless rows added since exclude it.
  if (constraints_.SatisfiedBy(checker_.best())) {
    options.initial_solution = milp.ColumnsOf(objectives_, checker_.best());
  }
  SolveCallbacks callbacks(*this, milp);
  return solver_.Solve(milp.model, options, callbacks);
}

bool ExactSearch::OnCandidate(std::span<const int64_t> x) {
  if (checker_.Check(x) == CandidateVerdict::kImproved) Report();
  const bool new_rows = checker_.rows_added() > round_start_rows_;
  if (new_rows && tuning_.restart_at_invalid_incumbent) return false;
  return !clock_.ShouldStop();
}

bool ExactSearch::OnBound(double bound, int64_t nodes) {
  round_bound_ = std::max(round_bound_, bound);
  round_nodes_ = nodes;
  if (clock_.ElapsedSeconds() - last_report_ >= kReportIntervalSeconds) Report();
  return !clock_.ShouldStop();
}

absl::StatusOr<double> ExactSearch::RelaxationBound() {
  ISPQ_ASSIGN_OR_RETURN(const QuantizationMilp milp,
                        BuildQuantizationMilp(objectives_, constraints_, checker_.best()));
  ISPQ_ASSIGN_OR_RETURN(const LpResult relaxation, solver_.SolveRelaxation(milp.model));
  return relaxation.status == LpStatus::kOptimal ? relaxation.objective : kNoBound;
}

absl::StatusOr<bool> ExactSearch::SwitchToFailsafeIfEmpty() {
  if (used_failsafe_ || constraints_.SatisfiedBy(checker_.best())) return false;
  const MilpModel feasibility = BuildFeasibilityModel(bundles_.num_bundles(), constraints_);
  ISPQ_ASSIGN_OR_RETURN(const LpResult relaxation, solver_.SolveRelaxation(feasibility));
  if (relaxation.status == LpStatus::kOptimal) return false;
  constraints_.UseFailsafeForms();
  used_failsafe_ = true;
  // Earlier proofs were about the default rows; start over from the row-free relaxation.
  ISPQ_ASSIGN_OR_RETURN(bound_, RelaxationBound());
  return true;
}

void ExactSearch::Report() {
  last_report_ = clock_.ElapsedSeconds();
  if (observer_ == nullptr) return;
  ProgressEvent event;
  event.phase = QuantizationPhase::kExact;
  event.iteration = nodes_ + round_nodes_;
  event.separation_round = solves_;
  event.objective = checker_.best_objective();
  event.violated_constraints = 0;
  event.separating = true;
  event.elapsed_seconds = last_report_;
  if (CurrentBound() > kNoBound) event.lower_bound = CurrentBound();
  if (observer_->WantsQuantization()) {
    q_ = constraints_.ArcValues(checker_.best());
    event.q = q_;
  }
  observer_->OnProgress(event);
}

ExactOutcome ExactSearch::Finish(bool proven) const {
  ExactOutcome outcome;
  outcome.q = constraints_.ArcValues(checker_.best());
  outcome.objective = checker_.best_objective();
  // Optimal within kImprovementTolerance: the proof is that nothing is better by more.
  outcome.lower_bound = proven ? outcome.objective : std::min(bound_, outcome.objective);
  outcome.termination = proven             ? Termination::kOptimal
                        : clock_.stopped() ? clock_.termination()
                                           : Termination::kConverged;
  outcome.milp_solves = solves_;
  outcome.milp_nodes = nodes_;
  outcome.incumbents = checker_.checked();
  outcome.separation_rows = constraints_.SeparationRowsOverArcs();
  return outcome;
}

}  // namespace

absl::StatusOr<ExactOutcome> RunExactQuantization(const TMesh& mesh, const QuantizeOptions& options,
                                                  std::span<const int64_t> start,
                                                  MilpSolver& solver, const ExactTuning& tuning,
                                                  ProgressObserver* observer, RunClock& clock) {
  ExactSearch search(mesh, options, start, solver, tuning, observer, clock);
  return search.Run();
}

}  // namespace ispq
