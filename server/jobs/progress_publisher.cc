// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/progress_publisher.h"

#include <utility>

#include "core/proto/quantization_proto.h"

namespace ispq::server {

ProgressPublisher::ProgressPublisher(Job& job, absl::Duration progress_interval,
                                     absl::Duration intermediate_interval)
    : job_(job),
      progress_interval_(absl::ToChronoNanoseconds(progress_interval)),
      intermediate_interval_(
          intermediate_interval > absl::ZeroDuration()
              ? std::optional<Clock::duration>(absl::ToChronoNanoseconds(intermediate_interval))
              : std::nullopt) {}

bool ProgressPublisher::WantsQuantization() const {
  if (!intermediate_interval_.has_value()) return false;
  return !last_intermediate_.has_value() ||
         Clock::now() - *last_intermediate_ >= *intermediate_interval_;
}

bool ProgressPublisher::Improves(const ProgressEvent& event) const {
  if (!sent_objective_.has_value()) return true;
  if (event.separating != sent_separating_) return event.separating;
  return event.objective < *sent_objective_;
}

void ProgressPublisher::OnProgress(const ProgressEvent& event) {
  const Clock::time_point now = Clock::now();
  const bool phase_changed = last_phase_ != event.phase;
  const bool progress_due =
      !last_progress_.has_value() || now - *last_progress_ >= progress_interval_;
  if (phase_changed || progress_due) {
    job_.PublishProgress(ProgressToProto(event));
    last_progress_ = now;
    last_phase_ = event.phase;
  }
  // The solver fills q only when WantsQuantization() said so, i.e. when the interval is over.
  if (!event.q.empty() && WantsQuantization() && Improves(event)) {
    v1::IntermediateQuantization intermediate;
    *intermediate.mutable_progress() = ProgressToProto(event);
    intermediate.mutable_q()->Reserve(static_cast<int>(event.q.size()));
    for (int64_t value : event.q) intermediate.add_q(static_cast<int32_t>(value));
    job_.PublishIntermediate(std::move(intermediate));
    last_intermediate_ = now;
    sent_separating_ = event.separating;
    sent_objective_ = event.objective;
  }
}

}  // namespace ispq::server
