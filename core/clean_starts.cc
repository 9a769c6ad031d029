// SPDX-License-Identifier: Apache-2.0
#include "core/clean_starts.h"

#include <algorithm>
#include <limits>

#include "core/invariant.h"

namespace ispq {

CleanStarts::CleanStarts(const TMesh& mesh, const BlockNodeSlots& slots, int num_configs)
    : mesh_(mesh), slots_(slots), reach_(num_configs, kUnknown), bound_(num_configs) {}

void CleanStarts::StartSearch(std::span<const int64_t> q) {
  if (last_q_.size() != q.size()) {
    std::fill(reach_.begin(), reach_.end(), kUnknown);
    last_q_.assign(q.begin(), q.end());
    distance_.assign(mesh_.num_nodes(), kFar);
    return;
  }
  if (!MarkChangedArcs(q)) {
    std::fill(distance_.begin(), distance_.end(), kFar);
    return;
  }
  MeasureDistances();
  std::copy(q.begin(), q.end(), last_q_.begin());
}

bool CleanStarts::MarkChangedArcs(std::span<const int64_t> q) {
  arc_changed_.assign(q.size(), 0);
  bool any = false;
  for (size_t a = 0; a < q.size(); ++a) {
    if (q[a] == last_q_[a]) continue;
    arc_changed_[a] = 1;
    any = true;
  }
  return any;
}

void CleanStarts::MeasureDistances() {
  distance_.assign(mesh_.num_nodes(), kFar);
  frontier_.clear();
  const auto make_dirty = [this](NodeId n) {
    if (distance_[n] == 0) return;
    distance_[n] = 0;
    frontier_.push_back(n);
  };
  for (ArcId a = 0; a < static_cast<ArcId>(arc_changed_.size()); ++a) {
    if (arc_changed_[a] == 0) continue;
    make_dirty(mesh_.tail(HalfarcOf(a, false)));
    make_dirty(mesh_.head(HalfarcOf(a, false)));
  }
  for (BlockId b = 0; b < mesh_.num_blocks(); ++b) {
    if (!slots_.PositionsDependOn(b, arc_changed_)) continue;
    for (SlotId s = slots_.first_slot(b); s < slots_.end_slot(b); ++s) {
      make_dirty(slots_.node_of(s));
    }
  }
  const int max_reach = [this] {
    int most = -1;
    for (uint8_t r : reach_) {
      if (r != kUnknown) most = std::max<int>(most, r);
    }
    return most;
  }();
  // Breadth-first over arcs, as far as the longest remembered reach: beyond it nothing is read.
  for (int d = 1; d <= max_reach && !frontier_.empty(); ++d) {
    next_frontier_.clear();
    for (NodeId n : frontier_) {
      for (HalfarcId h : mesh_.outgoing_halfarcs(n)) {
        const NodeId m = mesh_.head(h);
        if (distance_[m] != kFar) continue;
        distance_[m] = static_cast<uint8_t>(d);
        next_frontier_.push_back(m);
      }
    }
    std::swap(frontier_, next_frontier_);
  }
}

void CleanStarts::RecordClean(int config, int reach, const std::array<int64_t, 3>& along) {
  ISPQ_INVARIANT(reach >= 0, "a reach counts arc hops");
  reach_[config] = reach > kMaxReach ? kUnknown : static_cast<uint8_t>(reach);
  for (int axis = 0; axis < 3; ++axis) {
    ISPQ_INVARIANT(along[axis] >= 0, "a walk bound sums negative lengths");
    bound_[config][axis] =
        static_cast<int32_t>(std::min<int64_t>(along[axis], std::numeric_limits<int32_t>::max()));
  }
}

void CleanStarts::ForgetFrom(int first) {
  std::fill(reach_.begin() + first, reach_.end(), kUnknown);
}

}  // namespace ispq
