// SPDX-License-Identifier: Apache-2.0
// The product's verdict on separation: which searches a q must pass to be called separating.
//
// The lazy separation search is a heuristic (core/README.md, section Walks and their order): it
// settles every node once per search, so which violations it sees depends on which walk reaches a
// node first. The paper's search (sorted block boxes) and the reference implementation's (unsorted
// block boxes; core/README.md, section Block admissibility and the two block-box modes) therefore
// each find violations the other misses: the first around sign-flipping transitions, the second
// where the sorted search's larger fan settles a node in a different chart around a singular arc
// (the `hand` model of MC3D's test resources, issue 13). Every row either finds is a sufficient
// separation condition, so the product requires both to come back empty: a result it certifies is
// then separating by the paper's search and by upstream's own check.
//
// The searches and their mesh tables are built by the first call that searches (the start
// configurations alone took 0.07 s on a 100k-arc assembly part and 0.24 s at 300k): a run's first
// valid q, the layered start's, needs no search (core/README.md, section Hopeless walks), so the
// run reports it before paying for them.
//
// A check remembers the last q that passed every search of its rule, so that the validator's
// FindAllViolations on the q a run ends with (which the run's own last search passed) costs a
// comparison instead of both searches again: 17% of a one-shot run's Quantize() on the shared
// meshes (callgrind, median over 11 meshes x levels 5/25/100). The verdict is the same by
// construction: a search is a deterministic function of the mesh, its mode and q (core/README.md,
// case T13), and a search that reports nothing has run to its end.
#ifndef ISPQ_CORE_SEPARATION_CHECK_H_
#define ISPQ_CORE_SEPARATION_CHECK_H_

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "core/separation_search.h"
#include "core/tmesh.h"

namespace ispq {

enum class SeparationRule : uint8_t {
  kBothSearches,     // the product's rule: the reference search and the sorted search
  kReferenceSearch,  // upstream's verdict alone, to reproduce upstream results
};

class SeparationCheck {
 public:
  // The mesh must outlive this object; one instance serves one thread. Builds nothing yet.
  SeparationCheck(const TMesh& mesh, SeparationRule rule);

  // The violations of the first search, in the order reference then sorted, that finds any;
  // empty iff q passes every search of the rule. q must be consistent.
  std::vector<SeparationViolation> FindFirstViolations(std::span<const int64_t> q);
  // The same, handed to `sink` as they are found (core/separation_search.h); returns how many.
  int64_t FindFirstViolations(std::span<const int64_t> q,
                              const std::function<bool(SeparationViolation&)>& sink);

  // The violations of every search of the rule, reference search first. Nothing, without
  // searching, for the last q that FindFirstViolations found clean.
  std::vector<SeparationViolation> FindAllViolations(std::span<const int64_t> q);

  // What the check was built for: users handed a check confirm it is the one they need.
  const TMesh& mesh() const { return *mesh_; }
  SeparationRule rule() const { return rule_; }

 private:
  // The searches of the rule, built on first use.
  std::vector<SeparationSearch>& Searches();

  const TMesh* mesh_;
  SeparationRule rule_;
  std::vector<SeparationSearch> searches_;
  // The last q on which every search came back empty (valid only if has_clean_q_).
  std::vector<int64_t> clean_q_;
  bool has_clean_q_ = false;
};

}  // namespace ispq

#endif  // ISPQ_CORE_SEPARATION_CHECK_H_
