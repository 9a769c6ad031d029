// SPDX-License-Identifier: Apache-2.0
// The judge of the exact mode's candidate quantizations (paper section 3, step 3, applied to every
// incumbent of the MILP, not only to its optimum): a candidate that satisfies the consistency and
// simple rows goes through the product's separation check (core/separation_check.h). If the check
// finds nothing the candidate is valid and, if it beats the best valid q so far, becomes the best;
// otherwise the rows of the violations it found join the constraints, so that the next MILP
// excludes it. Candidates seen before are not checked again (CBC reports some solutions twice). See
// core/README.md, section Exact mode.
#ifndef ISPQ_CORE_EXACT_INCUMBENT_CHECKER_H_
#define ISPQ_CORE_EXACT_INCUMBENT_CHECKER_H_

#include <cstdint>
#include <set>
#include <span>
#include <vector>

#include "core/exact/bundle_objective.h"
#include "core/exact/quantization_constraints.h"
#include "core/separation_check.h"
#include "core/tmesh.h"

namespace ispq {

enum class CandidateVerdict : uint8_t {
  kSeen,         // checked before
  kNotFeasible,  // violates a consistency or simple row (a solver's rounding noise)
  kValid,        // passes the separation check but is not better than the best
  kImproved,     // valid and better: the new best
  kSeparated,    // the check found violations; their rows were added
};

class IncumbentChecker {
 public:
  // Everything referenced must outlive the checker; `start` is a valid q per bundle (the ISP
  // result) and becomes the first best.
  IncumbentChecker(const TMesh& mesh, SeparationRule rule, const BundleObjectives& objectives,
                   QuantizationConstraints& constraints, std::vector<int64_t> start);

  CandidateVerdict Check(std::span<const int64_t> x);

  std::span<const int64_t> best() const { return best_; }
  double best_objective() const { return best_objective_; }
  int64_t checked() const { return checked_; }
  // Separation rows added so far (a caller compares counts to see whether a round added any).
  int64_t rows_added() const { return rows_added_; }

 private:
  const BundleObjectives& objectives_;
  QuantizationConstraints& constraints_;
  SeparationCheck separation_;
  std::vector<int64_t> best_;
  double best_objective_;
  std::set<std::vector<int64_t>> seen_;
  int64_t checked_ = 0;
  int64_t rows_added_ = 0;
};

}  // namespace ispq

#endif  // ISPQ_CORE_EXACT_INCUMBENT_CHECKER_H_
