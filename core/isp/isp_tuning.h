// SPDX-License-Identifier: Apache-2.0
// The choices of the ISP engine that stay switchable, each because switching it measurably
// changes the result. The measurement is noted with each: the change of the mean objective ratio
// to the reference ISP results and of the LP solves on the 496 shared instances when only that
// choice is switched (ispq_tuning_bench). Production runs the defaults.
//
// Choices that measured no effect were removed and their defaults kept: the reference's step
// damping of 1/3 (+12% LP solves), block-extent rows joining lazily with the simple rows (+3%),
// repeated greedy passes (+13%), repairs in ordinary greedy passes (+0.004% objective, +23%), and
// the tiered weights of eq. 4 for separating solves (+2%) all left every objective unchanged.
#ifndef ISPQ_CORE_ISP_ISP_TUNING_H_
#define ISPQ_CORE_ISP_ISP_TUNING_H_

namespace ispq {

struct IspTuning {
  // When the sheet of a root does not improve the objective, block the bundles it made worse
  // from moving that way and solve again, up to this many times (thorough passes only). The
  // tier weights of eq. 4 cannot tell a slightly favorable crossing of the target from a
  // slightly unfavorable one, so the cheapest sheet is often not an improving one while an
  // improving one exists (0 attempts: +0.137%, 6 instances worse, 23% fewer LP solves). A second
  // and third attempt changed no q on the shared instances nor on the 10k-arc scaling meshes and
  // cost 14% more LP solves on the shared set, 15-20% on the large meshes.
  int repair_attempts = 1;
  // On subproblems of at least cover_min_bundles bundles, a non-improving sheet is repaired only
  // if it loses at most this much objective per arc it moves (the sheet's gain over the arcs of
  // its bundles times their moves). There repairs were a third of the thorough pass's solves,
  // and the most expensive (blocking the worsened bundles makes long detours), yet only 11 of
  // 4,100 improved anything in the scaling runs (1k-100k arcs, three families, levels 5/25/100),
  // every one of them from a sheet losing at most 0.17 per moved arc: a sheet far from improving
  // is not turned around by steering. With 0.25 all 45 scaling runs end with the objective they
  // end with when every sheet is repaired, in 60-75% of the CPU at 10k-100k arcs and levels 5/25
  // (level 100: 90-100%); with no repairs on large subproblems one run ended 4.2% worse. Smaller
  // subproblems (every shared instance) repair every sheet.
  double repair_max_loss_per_arc = 0.25;
  // How a rational LP vertex becomes an integer sheet. false: multiply by the least common
  // denominator (the paper, section 4.3.1). true: first dive toward an integer vertex by fixing
  // the fractional bundle closest to its next integer (away from zero) and re-solving, as the
  // reference implementation does, falling back to the lcd when the dive turns infeasible
  // (false: +0.070%, 3% fewer LP solves; the multiplied sheet is often far from locally minimal).
  bool integer_dive = true;
  // Run the final thorough pass (both directions, no early stop) before accepting a result
  // (false: +0.62%, 62% fewer LP solves).
  bool thorough_final_pass = true;
  // In subproblems of at least this many bundles, a greedy pass does not solve for a
  // (root, direction) that a non-improving sheet of an earlier root moved that way (since the
  // last applied sheet or new row) and takes that sheet as its answer (core/isp/sheet_coverage.h).
  // Each check is one O(subproblem) solve, and the final thorough pass alone was 80-90% of them
  // on large parts, so the cost grew as size^2. On the scaling meshes (3k-30k arcs, three
  // families, levels 5/25/100; CPU against the solver without the shortcut): in thorough passes
  // only, 3-5x less CPU at 3k arcs and 5-12x at 30k, objective +0.15% on average (12 of 36 runs
  // worse, at most +1.65%); in ordinary passes too, the same objectives on all 27 runs compared,
  // 20-40% less CPU again at 10k-30k and the first valid q twice as early. On the shared
  // instances, which have at most 65 bundles, it would lose 5 instances (up to +20%): below the
  // threshold every check is solved.
  int cover_min_bundles = 256;
  // A thorough pass pumps the roots of a subproblem of fewer than this many bundles both ways,
  // those of larger ones toward their targets only. Pumping a root away from its target improves
  // the objective only through the other bundles the sheet moves toward theirs, and pumping those
  // finds such sheets. On large parts the away checks were most of the thorough pass's solves
  // (at 100k arcs, 1,500-3,900 of the 3,000-6,300 solves of a run) and were accepted 3 times in
  // 27 scaling runs (10k-100k arcs, three families, levels 5/25/100). Toward targets only, at
  // 10k-200k arcs: 0.24-0.80x the CPU in 34 of 36 runs; side by side (paired runs, median):
  // 100k single part 0.51x at level 5 and 0.61x at level 100, 200k slabs 0.26x, but 200k single
  // at level 100 only 0.92x, though its LP solves halve (the away solves were the cheap ones
  // there). Objective ratio over all 72 runs (100 to 200k arcs): 1.00007 on average, 7 better,
  // 5 worse, at most +0.47%. The shared instances are all below the threshold; at 0 they would
  // take 34% fewer LP solves for +0.007% objective.
  int away_checks_max_bundles = 256;
  // Subproblems of at least this many bundles descend in bulk: each greedy pass solves the LP of
  // the best combination of unit moves over the whole subproblem (exact objective changes, every
  // bundle boxed at one unit; SheetRequest::unit_moves) and applies it, until none improves,
  // instead of pumping root after root. A sheet with moves of one unit is such a combination, so
  // once the bulk LP finds nothing, no root's unit sheet can improve either.
  int bulk_descent_min_bundles = 256;
  // On meshes of at least bulk_descent_min_bundles bundles whose consistent q are potential
  // differences (core/bundle_potentials.h), solve the sheet LPs without a root (bulk descent,
  // separating updates) as min-cost flows (core/isp/sheet_network.h), the LP answering where the
  // flow cannot. The same optima (a split side row aside); among tied optima the flow may pick
  // another. On the assembly benchmark (tests/bench/large) every run compared ended with the same
  // objective: 300k arcs of assembly16 at levels 5 / 25 / 100 in 2.4 / 9.9 / 8.0 s CPU instead of
  // 14 / 54 / 82 s, 10^6 arcs in 17 / 37 / 33 s instead of 236 / 759 / 1097 s. The shared
  // instances are unchanged (too few bundles).
  bool bulk_descent_as_flow = true;
  // Separate in the failsafe mode of App. B only (structural rows in their non-negative form,
  // non-deflating sheets), skipping the default and non-deflating modes. The default mode
  // succeeds on every shared instance (true: +0.000%), so this is what lets tests exercise the
  // failsafe mode, the safety net for when it does not.
  bool failsafe_separation_only = false;
  // At most this many (>= 1) new structural rows per subproblem (of the row's first bundle) join
  // the active rows per separation search; once
  // they are enforced, the search runs again before any greedy descent. A row names one path
  // between two entities, a sufficient condition that is often stronger than needed, and the
  // sheets that separate the other paths of a search often separate those entities too: on `hand`
  // (MC3D test resources) at level 100 the first search reports 46 rows, enforcing all of them at
  // once costs +364 and the run ends at 612; two at a time it ends at 377 (upstream ISP: 412).
  // Unbounded: +0.78%, 6% fewer LP solves; 1: -0.006%, +2% LP solves; 4: +0.12%, one instance
  // 28% worse. Per subproblem, because independent parts do not help each other: with one cap for
  // the whole mesh, 160 disjoint copies of s07c_notch took 884 rounds and 11.1 s instead of 6
  // rounds and 0.95 s (the shared set: 495 of 496 q identical, the other one no worse).
  int max_new_rows_per_search = 2;
  // ... or one per this many bundles of the subproblem, if that is more (0: never more). A large
  // part's search reports violations all over it, far apart, that no one sheet separates
  // together; two per round made a 100k-arc part take 40 rounds, each a search and a separating
  // update. On the 100k/300k-arc benchmark parts (tests/bench/large) with 4000, against 2 alone:
  // the same q in all six runs measured, rounds 40 -> 21, 30 -> 16, 27 -> 14, 5 -> 3, 28 -> 6,
  // CPU -11% to -24% (single-part family unchanged: its subproblems stay under 8000 bundles). With
  // 1000, one run (assembly16, 100k arcs, level 100) ended 1.7% worse and took 1.6x the CPU. Real
  // meshes have far fewer bundles per subproblem: the shared instances are unchanged.
  int bundles_per_extra_new_row = 4000;
  // On meshes of at least this many arcs, the run first traces the layered start
  // (core/isp/layered_start.h): a q >= 1 on every arc, reported at once (phase LAYERS) if the
  // search finds it separating, and the result if the run finds no better valid q (a run stopped
  // early returns it). The ISP path is unchanged: it still starts from q = 0. On the single-part
  // scaling meshes the first valid q then comes after 15-20% of the solve at 10k arcs, 9-14% at
  // 30k, 3-5% at 100k and 1-2% at 200k (before: 44-58%, 32-66%, 32-53%, 22-55%), the layers
  // themselves taking 4, 15, 54 and 114-157 ms; side by side a run takes 1.00-1.04x the CPU.
  // Below the threshold a whole run takes hundredths of a second: with 0, the shared instances
  // end with the same q and LP solves in 3% more CPU time (ispq_tuning_bench).
  int layered_start_min_arcs = 2000;
  // Start the descent from the layered start's q, with the simple rows active, instead of q = 0,
  // when the mesh has one (layered_start_min_arcs) and it is separating.
  bool descend_from_layered_start = true;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_ISP_TUNING_H_
