// SPDX-License-Identifier: Apache-2.0
// The roots of the greedy descent (paper Alg. 1) and when to pump them again (core/README.md,
// section The greedy queue and passes).
//
// Roots are bundles, popped furthest from their targets first (ties: the smaller id). Every
// entry carries a stamp; queuing a bundle again outdates its older entries, which are skipped.
// After a root's solve the queue records the bundles that solve depended on (its sheet, or, when
// the LP was infeasible, the root and the bundles sharing an active row with it); an accepted
// sheet then re-queues exactly the roots whose last solve depended on a bundle it moved or on a
// row whose slack it changed, instead of re-solving every root.
//
// The queue outlives a pass: the roots a pass did not reach stay queued, and the dependencies of
// the roots it did reach stay recorded, so the next pass starts from what changed since (sheets
// applied in between, rows that joined) instead of from every bundle again. A new row cannot
// change the answer of a root whose sheet leaves all the row's bundles alone: that sheet still
// satisfies it and the LP only lost solutions.
//
// What an answer depended on (a support) is stored once, however many roots share it: on a large
// part most checks are answered by another root's sheet (core/isp/sheet_coverage.h), and copying
// that sheet into per-bundle lists for every root it answered took a third of the memory of a
// 100k-arc run.
#ifndef ISPQ_CORE_ISP_GREEDY_QUEUE_H_
#define ISPQ_CORE_ISP_GREEDY_QUEUE_H_

#include <cstdint>
#include <optional>
#include <queue>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/arc_bundles.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/inequality_rows.h"
#include "core/isp/integer_sheet.h"

namespace ispq {

class GreedyQueue {
 public:
  // Both must outlive the queue.
  GreedyQueue(const BundleQuantization& quantization, const InequalityRows& rows);

  // Every bundle queued once, every recorded dependency forgotten.
  void Reset();
  // Whether Reset() ran since construction.
  bool started() const { return started_; }
  // Bundle entries of the recorded supports, used or not yet dropped: at most twice those of the
  // current supports (the last answer of each root) or 32 per bundle, whichever is more.
  int64_t num_recorded_dependencies() const { return static_cast<int64_t>(pool_.size()); }
  // The next root whose entry is current, or nullopt when none is left.
  std::optional<BundleId> Pop();
  // What the last solve of `root` depended on: the bundles of its sheet (`support`), or, for an
  // infeasible solve (empty support), the slack of the active rows around the root. A `shared`
  // id names a support several roots record (a covering sheet): it is stored once.
  void RecordDependencies(BundleId root, std::span<const BundleId> support,
                          std::optional<uint64_t> shared = std::nullopt);
  // After `sheet` was applied: re-queues every root whose last solve depended on what changed,
  // and the bundles of the sheet themselves.
  void RequeueAfter(const IntegerSheet& sheet);
  // After rows over these bundles joined the active rows: re-queues every root whose last solve
  // depended on one of them.
  void RequeueUsersOf(std::span<const BundleId> bundles);

 private:
  struct Entry {
    double priority;
    BundleId bundle;
    int32_t stamp;
  };
  // Max-heap on priority; among equal priorities the smaller bundle id first (determinism).
  struct Order {
    bool operator()(const Entry& x, const Entry& y) const {
      if (x.priority != y.priority) return x.priority < y.priority;
      return x.bundle > y.bundle;
    }
  };

  void Push(BundleId b);
  // Makes `support` the current one of `root`.
  void Attach(BundleId root, int32_t support);
  // A new support over these bundles; returns its id.
  int32_t AddSupport(std::span<const BundleId> bundles);
  // Re-queues the current users of bundle c (once per epoch) and forgets them.
  void RequeueUsers(BundleId c);
  // Drops the supports no root depends on any more, once they outnumber the current ones by far
  // (a support is otherwise only dropped when one of its bundles changes).
  void DropOutdatedDependencies();
  // Marks b in the current epoch; true if it was not marked yet.
  bool Mark(BundleId b);

  const BundleQuantization& quantization_;
  const InequalityRows& rows_;
  std::priority_queue<Entry, std::vector<Entry>, Order> heap_;
  std::vector<int32_t> stamp_;
  // Supports: the bundles of support s are pool_[begin_[s], begin_[s + 1]); its dependents are
  // the roots whose current support it is (support_of_root_, -1 while a root is queued);
  // supports_of_bundle_ indexes them by bundle. A support dies when one of its bundles changes
  // (its dependents are queued again) or when no root depends on it any more.
  std::vector<BundleId> pool_;
  std::vector<int64_t> begin_{0};
  std::vector<std::vector<BundleId>> dependents_;
  std::vector<int32_t> dependent_count_;  // -1 once dead
  std::vector<std::vector<int32_t>> supports_of_bundle_;
  std::vector<int32_t> support_of_root_;
  std::unordered_map<uint64_t, int32_t> shared_support_;
  int64_t drop_threshold_;  // dead supports are dropped when the pool is larger than this
  bool started_ = false;
  std::vector<uint32_t> mark_;
  uint32_t epoch_ = 0;
  std::vector<BundleId> affected_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_GREEDY_QUEUE_H_
