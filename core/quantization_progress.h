// SPDX-License-Identifier: Apache-2.0
// Anytime reporting of a running quantization. The algorithm calls the observer on its own
// thread at each accepted sheet and each separation round; observers must be cheap (copy what
// they need and return) because they run inside the solve loop.
#ifndef ISPQ_CORE_QUANTIZATION_PROGRESS_H_
#define ISPQ_CORE_QUANTIZATION_PROGRESS_H_

#include <cstdint>
#include <optional>
#include <span>

namespace ispq {

enum class QuantizationPhase : uint8_t {
  kGreedy,      // greedy descent: sheets that bring arcs closer to their targets
  kSeparation,  // separating sheet updates after a lazy separation round
  kFailsafe,    // the failsafe (non-negative rows only) separation mode of App. B
  kFinal,       // the last thorough greedy pass and the final checks
  kExact,       // exact mode: the MILP's branch and bound with its lazy separation loop
  kLayers,      // the anytime start of large runs: a q traced from the parametrization's layers
};

const char* QuantizationPhaseName(QuantizationPhase phase);

struct ProgressEvent {
  QuantizationPhase phase;
  int64_t iteration;             // accepted sheets so far
  int64_t separation_round;      // lazy separation rounds so far
  double objective;              // d(q, s*l) of the current q
  int64_t violated_constraints;  // known rows (simple and separation) the current q violates
  bool separating;               // q satisfies every known row and the last search found nothing
  double elapsed_seconds;
  int64_t lp_solves = 0;       // LP solves so far (QuantizeStats::lp_solves)
  std::span<const int64_t> q;  // current q, only if the observer WantsQuantization()
  // Exact mode: no q satisfying the separation rows found so far is better than this.
  std::optional<double> lower_bound = std::nullopt;
};

class ProgressObserver {
 public:
  virtual ~ProgressObserver() = default;
  virtual void OnProgress(const ProgressEvent& event) = 0;
  // Copying q costs O(arcs); the algorithm fills ProgressEvent::q only when this is true.
  virtual bool WantsQuantization() const { return false; }
};

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZATION_PROGRESS_H_
