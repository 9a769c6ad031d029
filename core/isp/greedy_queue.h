// The roots of the greedy descent (paper Alg. 1) and when to pump them again.
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
#ifndef ISPQ_CORE_ISP_GREEDY_QUEUE_H_
#define ISPQ_CORE_ISP_GREEDY_QUEUE_H_

#include <cstdint>
#include <optional>
#include <queue>
#include <span>
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
  // Dependencies recorded and not yet used or dropped: at most twice the current ones (those of
  // each root's last solve) or 32 per bundle, whichever is more.
  int64_t num_recorded_dependencies() const { return num_dependencies_; }
  // The next root whose entry is current, or nullopt when none is left.
  std::optional<BundleId> Pop();
  // What the last solve of `root` depended on: the bundles of its sheet (`support`), or, for an
  // infeasible solve (empty support), the slack of the active rows around the root.
  void RecordDependencies(BundleId root, std::span<const BundleId> support);
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
  // Re-queues the current users of bundle c (once per epoch) and forgets them.
  void RequeueUsers(BundleId c);
  // Drops the recorded dependencies of solves that are no longer a root's last one, once they
  // outnumber the bundles by far (they are only dropped otherwise when their bundle changes).
  void DropOutdatedDependencies();
  // Marks b in the current epoch; true if it was not marked yet.
  bool Mark(BundleId b);

  const BundleQuantization& quantization_;
  const InequalityRows& rows_;
  std::priority_queue<Entry, std::vector<Entry>, Order> heap_;
  std::vector<int32_t> stamp_;
  // Per bundle, the (root, stamp) of the solves that depended on it.
  std::vector<std::vector<std::pair<BundleId, int32_t>>> users_;
  int64_t num_dependencies_ = 0;
  int64_t drop_threshold_;  // outdated records are dropped when there are more records than this
  bool started_ = false;
  std::vector<uint32_t> mark_;
  uint32_t epoch_ = 0;
  std::vector<BundleId> affected_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_ISP_GREEDY_QUEUE_H_
