// SPDX-License-Identifier: Apache-2.0
#include "server/model/job_event_log.h"

#include <algorithm>
#include <utility>

namespace ispq::server {
namespace {

bool IsSnapshot(v1::QuantizeEvent::KindCase kind) {
  return kind == v1::QuantizeEvent::kProgress || kind == v1::QuantizeEvent::kIntermediate;
}

}  // namespace

int64_t JobEventLog::Append(v1::QuantizeEvent event) {
  const v1::QuantizeEvent::KindCase kind = event.kind_case();
  if (IsSnapshot(kind)) {
    std::erase_if(kept_,
                  [kind](const v1::QuantizeEvent& kept) { return kept.kind_case() == kind; });
  } else if (kind == v1::QuantizeEvent::kResult || kind == v1::QuantizeEvent::kError) {
    std::erase_if(kept_, [](const v1::QuantizeEvent& kept) { return kept.has_intermediate(); });
  }
  const int64_t sequence = next_sequence_++;
  event.set_sequence(sequence);
  kept_.push_back(std::move(event));
  return sequence;
}

const v1::QuantizeEvent* JobEventLog::FirstAtOrAfter(int64_t from) const {
  const auto it = std::lower_bound(
      kept_.begin(), kept_.end(), from,
      [](const v1::QuantizeEvent& event, int64_t sequence) { return event.sequence() < sequence; });
  return it == kept_.end() ? nullptr : &*it;
}

bool JobEventLog::ended() const {
  if (kept_.empty()) return false;
  const v1::QuantizeEvent::KindCase kind = kept_.back().kind_case();
  return kind == v1::QuantizeEvent::kResult || kind == v1::QuantizeEvent::kError;
}

void JobEventLog::Restore(std::vector<v1::QuantizeEvent> kept, int64_t emitted) {
  kept_ = std::move(kept);
  next_sequence_ = emitted;
}

}  // namespace ispq::server
