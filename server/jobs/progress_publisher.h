// SPDX-License-Identifier: Apache-2.0
// The bridge from the solver's anytime reports (core/quantization_progress.h) to a job's events.
//
// The solver calls OnProgress at every accepted sheet and separation round, which can be
// thousands of times a second; the publisher turns that into at most one progress event per
// progress interval (plus one at each change of phase, and the very first report) and at most
// one intermediate quantization per intermediate interval, sent only when it improves on the
// last one sent (a separating q beats any non-separating one; otherwise the lower objective
// wins). It asks the solver for q (WantsQuantization) only when an intermediate event could be
// sent, so that the O(arcs) copy is not paid otherwise. Used by one solve on one thread.
#ifndef ISPQ_SERVER_JOBS_PROGRESS_PUBLISHER_H_
#define ISPQ_SERVER_JOBS_PROGRESS_PUBLISHER_H_

#include <chrono>
#include <optional>

#include "absl/time/time.h"
#include "core/quantization_progress.h"
#include "server/model/job.h"

namespace ispq::server {

class ProgressPublisher : public ProgressObserver {
 public:
  // `intermediate_interval` zero: no intermediate quantizations.
  ProgressPublisher(Job& job, absl::Duration progress_interval,
                    absl::Duration intermediate_interval);

  void OnProgress(const ProgressEvent& event) override;
  bool WantsQuantization() const override;

 private:
  using Clock = std::chrono::steady_clock;

  bool Improves(const ProgressEvent& event) const;

  Job& job_;
  const Clock::duration progress_interval_;
  const std::optional<Clock::duration> intermediate_interval_;
  std::optional<Clock::time_point> last_progress_;
  std::optional<QuantizationPhase> last_phase_;
  std::optional<Clock::time_point> last_intermediate_;
  // The last intermediate quantization sent, for Improves().
  bool sent_separating_ = false;
  std::optional<double> sent_objective_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_PROGRESS_PUBLISHER_H_
