// SPDX-License-Identifier: Apache-2.0
#include "core/proto/quantization_proto.h"

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/status_macros.h"

namespace ispq {
namespace {

v1::Phase PhaseToProto(QuantizationPhase phase) {
  switch (phase) {
    case QuantizationPhase::kGreedy:
      return v1::GREEDY;
    case QuantizationPhase::kSeparation:
      return v1::SEPARATION;
    case QuantizationPhase::kFailsafe:
      return v1::FAILSAFE;
    case QuantizationPhase::kFinal:
      return v1::FINAL;
    case QuantizationPhase::kExact:
      return v1::EXACT;
    case QuantizationPhase::kLayers:
      return v1::LAYERS;
  }
  return v1::PHASE_UNSPECIFIED;
}

v1::Termination TerminationToProto(Termination termination) {
  switch (termination) {
    case Termination::kConverged:
      return v1::CONVERGED;
    case Termination::kTimeLimit:
      return v1::TIME_LIMIT;
    case Termination::kInterrupted:
      return v1::INTERRUPTED;
    case Termination::kOptimal:
      return v1::OPTIMAL;
  }
  return v1::TERMINATION_UNSPECIFIED;
}

}  // namespace

ScalingChoice ScalingChoiceFromProto(const v1::Scaling& scaling) {
  switch (scaling.kind_case()) {
    case v1::Scaling::kFactor:
      return ScalingChoice::Factor(scaling.factor());
    case v1::Scaling::kLevelPercent:
      return ScalingChoice::LevelPercent(scaling.level_percent());
    case v1::Scaling::kTargetHexes:
      return ScalingChoice::TargetHexes(scaling.target_hexes());
    case v1::Scaling::KIND_NOT_SET:
      break;
  }
  return ScalingChoice();
}

absl::StatusOr<QuantizeOptions> QuantizeOptionsFromProto(const v1::QuantizationOptions& proto,
                                                         const TMesh& mesh) {
  QuantizeOptions options;
  ISPQ_ASSIGN_OR_RETURN(options.scaling,
                        ResolveScaling(ScalingChoiceFromProto(proto.scaling()), mesh));
  if (proto.has_mixed_sign()) options.mixed_sign = proto.mixed_sign();
  if (proto.has_decompose()) options.decompose = proto.decompose();
  options.per_arc_nonnegative = proto.per_arc_nonnegative();
  options.separation = proto.reference_block_boxes() ? SeparationRule::kReferenceSearch
                                                     : SeparationRule::kBothSearches;
  if (proto.has_time_limit()) {
    const double seconds = static_cast<double>(proto.time_limit().seconds()) +
                           1e-9 * static_cast<double>(proto.time_limit().nanos());
    if (!(seconds > 0)) {
      return absl::InvalidArgumentError(absl::StrCat("time limit ", seconds, "s is not positive"));
    }
    options.time_limit_seconds = seconds;
  }
  switch (proto.method()) {
    case v1::METHOD_UNSPECIFIED:
    case v1::METHOD_ISP:
      options.method = QuantizationMethod::kIsp;
      break;
    case v1::METHOD_EXACT:
      options.method = QuantizationMethod::kExact;
      break;
    default:
      return absl::InvalidArgumentError(
          absl::StrCat("method ", static_cast<int>(proto.method()), " is not a known method"));
  }
  if (proto.has_lower_bound()) {
    options.lower_bound = proto.lower_bound() ? LowerBoundMode::kAlways : LowerBoundMode::kNever;
  }
  ISPQ_RETURN_IF_ERROR(ValidateQuantizeOptions(mesh, options));
  return options;
}

v1::QuantizationResult QuantizationResultToProto(const QuantizeResult& result, double scaling,
                                                 const TMesh& mesh) {
  v1::QuantizationResult proto;
  proto.mutable_q()->Reserve(static_cast<int>(result.q.size()));
  // Quantize never returns a q outside +-kMaxArcLength (core/quantization_limits.h): no wrap.
  for (int64_t value : result.q) proto.add_q(static_cast<int32_t>(value));
  proto.set_objective(result.objective);
  proto.set_hexes(result.valid ? result.hexes : 0);
  proto.set_scaling(scaling);
  proto.set_valid(result.valid);
  proto.set_termination(TerminationToProto(result.termination));
  if (result.lower_bound.has_value()) proto.set_lower_bound(*result.lower_bound);
  if (result.gap.has_value()) proto.set_gap(*result.gap);
  proto.set_mesh_name(mesh.name());
  for (const SeparationRow& row : result.separation_rows) {
    v1::SeparationRow* out = proto.add_separation_rows();
    for (const LinearTerm& term : row.terms) {
      out->add_arcs(term.var);
      out->add_coefficients(term.coef);
    }
    out->set_rhs(row.rhs);
  }
  const QuantizeStats& s = result.stats;
  v1::QuantizationStats* stats = proto.mutable_stats();
  stats->set_lp_solves(s.lp_solves);
  stats->set_covered_checks(s.covered_checks);
  stats->set_lp_pivots(s.lp_pivots);
  stats->set_lp_refactorizations(s.lp_refactorizations);
  stats->set_lp_fallback_solves(s.lp_fallback_solves);
  stats->set_flow_solves(s.flow_solves);
  stats->set_lp_degenerate_pivots(s.lp_degenerate_pivots);
  stats->set_lp_stalled_solves(s.lp_stalled_solves);
  stats->set_sheets_inflating(s.sheets_inflating);
  stats->set_sheets_deflating(s.sheets_deflating);
  stats->set_sheets_mixed(s.sheets_mixed);
  stats->set_separating_updates(s.separating_updates);
  stats->set_failsafe_updates(s.failsafe_updates);
  stats->set_lcd_one(s.lcd_one);
  stats->set_lcd_two(s.lcd_two);
  stats->set_lcd_more(s.lcd_more);
  stats->set_separation_rounds(s.separation_rounds);
  stats->set_separation_rows(s.separation_rows);
  stats->set_subproblems(s.subproblems);
  stats->set_greedy_seconds(s.greedy_seconds);
  stats->set_layers_seconds(s.layers_seconds);
  stats->set_separation_search_seconds(s.separation_search_seconds);
  stats->set_separating_update_seconds(s.separating_update_seconds);
  stats->set_solve_seconds(s.solve_seconds);
  stats->set_lower_bound_seconds(s.lower_bound_seconds);
  stats->set_milp_solves(s.milp_solves);
  stats->set_milp_nodes(s.milp_nodes);
  stats->set_milp_incumbents(s.milp_incumbents);
  stats->set_exact_seconds(s.exact_seconds);
  return proto;
}

v1::Progress ProgressToProto(const ProgressEvent& event) {
  v1::Progress proto;
  proto.set_phase(PhaseToProto(event.phase));
  proto.set_iteration(event.iteration);
  proto.set_separation_round(event.separation_round);
  proto.set_objective(event.objective);
  proto.set_violated_constraints(event.violated_constraints);
  proto.set_separating(event.separating);
  proto.set_elapsed_seconds(event.elapsed_seconds);
  if (event.lower_bound.has_value()) proto.set_lower_bound(*event.lower_bound);
  proto.set_lp_solves(event.lp_solves);
  return proto;
}

absl::StatusOr<std::vector<int64_t>> QuantizationFromProto(const v1::QuantizationResult& result,
                                                           const TMesh& mesh) {
  if (result.q_size() != mesh.num_arcs()) {
    return absl::InvalidArgumentError(absl::StrCat("the result has ", result.q_size(),
                                                   " arc lengths but the mesh has ",
                                                   mesh.num_arcs(), " arcs"));
  }
  return std::vector<int64_t>(result.q().begin(), result.q().end());
}

}  // namespace ispq
