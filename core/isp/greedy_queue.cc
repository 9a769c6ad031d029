#include "core/isp/greedy_queue.h"

#include <algorithm>
#include <cmath>

namespace ispq {
namespace {

// Recorded dependencies per bundle beyond which outdated ones are dropped.
constexpr int64_t kDependenciesPerBundle = 32;

}  // namespace

GreedyQueue::GreedyQueue(const BundleQuantization& quantization, const InequalityRows& rows)
    : quantization_(quantization),
      rows_(rows),
      stamp_(quantization.num_bundles(), 0),
      users_(quantization.num_bundles()),
      drop_threshold_(kDependenciesPerBundle * quantization.num_bundles()),
      mark_(quantization.num_bundles(), 0) {}

void GreedyQueue::Reset() {
  started_ = true;
  heap_ = {};
  for (auto& list : users_) list.clear();
  num_dependencies_ = 0;
  for (BundleId b = 0; b < quantization_.num_bundles(); ++b) Push(b);
}

std::optional<BundleId> GreedyQueue::Pop() {
  while (!heap_.empty()) {
    const Entry top = heap_.top();
    heap_.pop();
    if (top.stamp == stamp_[top.bundle]) return top.bundle;
  }
  return std::nullopt;
}

void GreedyQueue::Push(BundleId b) {
  ++stamp_[b];
  heap_.push({std::abs(quantization_.mean_deviation(b)), b, stamp_[b]});
}

bool GreedyQueue::Mark(BundleId b) {
  if (mark_[b] == epoch_) return false;
  mark_[b] = epoch_;
  return true;
}

void GreedyQueue::RecordDependencies(BundleId root, std::span<const BundleId> support) {
  const int32_t stamp = stamp_[root];
  if (num_dependencies_ > drop_threshold_) DropOutdatedDependencies();
  if (!support.empty()) {
    for (BundleId c : support) users_[c].push_back({root, stamp});
    num_dependencies_ += static_cast<int64_t>(support.size());
    return;
  }
  // No sheet (infeasible LP): what could change that is the slack of the rows around the root.
  users_[root].push_back({root, stamp});
  ++num_dependencies_;
  for (const InequalityRows::Incidence& inc : rows_.rows_of_bundle(root)) {
    if (!rows_.active(inc.row)) continue;
    for (const LinearTerm& t : rows_.terms(inc.row)) users_[t.var].push_back({root, stamp});
    num_dependencies_ += static_cast<int64_t>(rows_.terms(inc.row).size());
  }
}

void GreedyQueue::DropOutdatedDependencies() {
  num_dependencies_ = 0;
  for (auto& list : users_) {
    std::erase_if(list, [&](const auto& user) { return user.second != stamp_[user.first]; });
    num_dependencies_ += static_cast<int64_t>(list.size());
  }
  // The current records alone can outnumber the bundles by far (a sheet crosses many bundles):
  // the next drop waits until the records doubled, so each scan is paid for by as many records.
  drop_threshold_ = std::max(drop_threshold_, 2 * num_dependencies_);
}

void GreedyQueue::RequeueUsers(BundleId c) {
  for (const auto& [root, stamp] : users_[c]) {
    if (stamp_[root] == stamp && Mark(root)) Push(root);
  }
  num_dependencies_ -= static_cast<int64_t>(users_[c].size());
  users_[c].clear();
}

void GreedyQueue::RequeueUsersOf(std::span<const BundleId> bundles) {
  ++epoch_;
  for (BundleId c : bundles) RequeueUsers(c);
}

void GreedyQueue::RequeueAfter(const IntegerSheet& sheet) {
  // Bundles whose value changed, plus those sharing an active row with them (whose rows' slack
  // changed).
  ++epoch_;
  affected_.clear();
  for (BundleId b : sheet.bundles) {
    if (Mark(b)) affected_.push_back(b);
    for (const InequalityRows::Incidence& inc : rows_.rows_of_bundle(b)) {
      if (!rows_.active(inc.row)) continue;
      for (const LinearTerm& t : rows_.terms(inc.row)) {
        if (Mark(t.var)) affected_.push_back(t.var);
      }
    }
  }
  // A new epoch marks the roots queued again, each once.
  ++epoch_;
  for (BundleId c : affected_) RequeueUsers(c);
  for (BundleId b : sheet.bundles) {
    if (Mark(b)) Push(b);
  }
}

}  // namespace ispq
