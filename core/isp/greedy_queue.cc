// SPDX-License-Identifier: Apache-2.0
#include "core/isp/greedy_queue.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace ispq {
namespace {

// Recorded dependencies per bundle beyond which outdated ones are dropped.
constexpr int64_t kDependenciesPerBundle = 32;

}  // namespace

GreedyQueue::GreedyQueue(const BundleQuantization& quantization, const InequalityRows& rows)
    : quantization_(quantization),
      rows_(rows),
      stamp_(quantization.num_bundles(), 0),
      supports_of_bundle_(quantization.num_bundles()),
      support_of_root_(quantization.num_bundles(), -1),
      drop_threshold_(kDependenciesPerBundle * quantization.num_bundles()),
      mark_(quantization.num_bundles(), 0) {}

void GreedyQueue::Reset() {
  started_ = true;
  heap_ = {};
  pool_.clear();
  begin_.assign(1, 0);
  dependents_.clear();
  dependent_count_.clear();
  for (auto& list : supports_of_bundle_) list.clear();
  std::fill(support_of_root_.begin(), support_of_root_.end(), -1);
  shared_support_.clear();
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
  Attach(b, -1);  // queued: what its last answer depended on no longer matters
  heap_.push({std::abs(quantization_.mean_deviation(b)), b, stamp_[b]});
}

bool GreedyQueue::Mark(BundleId b) {
  if (mark_[b] == epoch_) return false;
  mark_[b] = epoch_;
  return true;
}

void GreedyQueue::Attach(BundleId root, int32_t support) {
  const int32_t old = support_of_root_[root];
  if (old == support) return;
  if (old >= 0) --dependent_count_[old];
  support_of_root_[root] = support;
  if (support < 0) return;
  ++dependent_count_[support];
  dependents_[support].push_back(root);
}

int32_t GreedyQueue::AddSupport(std::span<const BundleId> bundles) {
  const int32_t support = static_cast<int32_t>(dependents_.size());
  pool_.insert(pool_.end(), bundles.begin(), bundles.end());
  begin_.push_back(static_cast<int64_t>(pool_.size()));
  dependents_.emplace_back();
  dependent_count_.push_back(0);
  for (BundleId c : bundles) supports_of_bundle_[c].push_back(support);
  return support;
}

void GreedyQueue::RecordDependencies(BundleId root, std::span<const BundleId> support,
                                     std::optional<uint64_t> shared) {
  if (static_cast<int64_t>(pool_.size()) > drop_threshold_) DropOutdatedDependencies();
  if (shared.has_value()) {
    const auto it = shared_support_.find(*shared);
    if (it != shared_support_.end() && dependent_count_[it->second] >= 0) {
      Attach(root, it->second);
      return;
    }
  }
  int32_t id;
  if (!support.empty()) {
    id = AddSupport(support);
  } else {
    // No sheet (infeasible LP): what could change that is the slack of the rows around the root.
    ++epoch_;
    affected_.clear();
    Mark(root);
    affected_.push_back(root);
    for (const InequalityRows::Incidence& inc : rows_.rows_of_bundle(root)) {
      if (!rows_.active(inc.row)) continue;
      for (const LinearTerm& t : rows_.terms(inc.row)) {
        if (Mark(t.var)) affected_.push_back(t.var);
      }
    }
    id = AddSupport(affected_);
  }
  if (shared.has_value()) shared_support_[*shared] = id;
  Attach(root, id);
}

void GreedyQueue::DropOutdatedDependencies() {
  // Keeps the supports some root depends on, renumbered in order and moved down in place (no
  // second copy of the pool at the peak), and rebuilds the index over them.
  const int32_t count = static_cast<int32_t>(dependents_.size());
  std::vector<int32_t> renumber(count, -1);
  int32_t kept = 0;
  int64_t write = 0;
  for (int32_t s = 0; s < count; ++s) {
    if (dependent_count_[s] <= 0) continue;
    renumber[s] = kept;
    const int64_t read = begin_[s], size = begin_[s + 1] - read;
    std::copy(pool_.begin() + read, pool_.begin() + read + size, pool_.begin() + write);
    begin_[kept] = write;
    write += size;
    std::erase_if(dependents_[s], [&](BundleId root) { return support_of_root_[root] != s; });
    if (kept != s) {  // a vector moved onto itself is left empty
      dependents_[kept] = std::move(dependents_[s]);
      dependent_count_[kept] = dependent_count_[s];
    }
    ++kept;
  }
  pool_.resize(write);
  begin_.resize(kept + 1);
  begin_[kept] = write;
  dependents_.resize(kept);
  dependent_count_.resize(kept);
  for (int32_t& s : support_of_root_) {
    if (s >= 0) s = renumber[s];
  }
  for (auto it = shared_support_.begin(); it != shared_support_.end();) {
    it->second = renumber[it->second];
    it = it->second < 0 ? shared_support_.erase(it) : std::next(it);
  }
  for (auto& list : supports_of_bundle_) list.clear();
  for (int32_t s = 0; s < kept; ++s) {
    for (int64_t k = begin_[s]; k < begin_[s + 1]; ++k) supports_of_bundle_[pool_[k]].push_back(s);
  }
  // The current supports alone can outnumber the bundles by far (a sheet crosses many bundles):
  // the next drop waits until the pool grew by a quarter, so each rebuild is paid for by a
  // quarter as many new entries, and at most a fifth of the pool is dead.
  drop_threshold_ = std::max(drop_threshold_, static_cast<int64_t>(pool_.size()) * 5 / 4);
}

void GreedyQueue::RequeueUsers(BundleId c) {
  for (int32_t s : supports_of_bundle_[c]) {
    if (dependent_count_[s] < 0) continue;  // died already
    for (BundleId root : dependents_[s]) {
      if (support_of_root_[root] == s && Mark(root)) Push(root);
    }
    // Every dependent is queued again (or was, in this epoch): the support is dead.
    dependent_count_[s] = -1;
    std::vector<BundleId>().swap(dependents_[s]);
  }
  supports_of_bundle_[c].clear();
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
