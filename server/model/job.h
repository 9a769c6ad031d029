// SPDX-License-Identifier: Apache-2.0
// One quantization job: its immutable specification, its state machine and its event log.
//
// States: QUEUED -> RUNNING -> SUCCEEDED | FAILED | CANCELLED, or QUEUED -> FAILED | CANCELLED
// for a job that never ran. A job is shared (std::shared_ptr) by the job store, the queue, the
// worker that runs it and the streams that watch it; it lives as long as the longest of them.
// All mutable state is guarded by one mutex. Watchers are notified after every event with the
// mutex released, so that a watcher may read the job from its notification.
//
// Memory: a job lets go of its mesh and its solver reservation when it ends (only the worker
// reads the mesh, and only while it runs), so the finished jobs the store retains hold their
// result and a few events, no mesh; with a memory budget, the job then accounts for what it
// retains (server/memory/memory_estimates.h) until it is destroyed.
//
// With a durable store (server/store/postgres/postgres_job_store.h) a job object is one of three
// views of a stored job: the one its replica created (New), which the store records through its
// event sink; a job a replica claimed from the store and runs (Resume), recorded the same way; or a
// mirror (Mirror) that answers lookups and feeds watchers on any replica and changes only by
// ApplyStored, with what the store says.
#ifndef ISPQ_SERVER_MODEL_JOB_H_
#define ISPQ_SERVER_MODEL_JOB_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/status/status.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "core/solve_interrupter.h"
#include "ispq/v1/service.pb.h"
#include "server/memory/memory_budget.h"
#include "server/model/job_event_log.h"
#include "server/model/job_event_sink.h"
#include "server/model/job_spec.h"

namespace ispq::server {

// Something that follows a job's events (a stream to a client).
class JobWatcher {
 public:
  virtual ~JobWatcher() = default;
  // Called on the thread that appended an event, without any lock of the job held. Must be
  // cheap and must not block: it runs inside the solver's progress callback.
  virtual void OnJobEvent() = 0;
};

class Job {
 public:
  // Emits the accepted event (number 0). `bound_to_call`: the job was started by a Quantize
  // call and ends with it. `budget` (may be null) accounts for the job once it has ended.
  Job(std::string id, JobSpec spec, bool bound_to_call, int queue_position, absl::Time now,
      MemoryBudget* budget = nullptr);
  Job(const Job&) = delete;
  Job& operator=(const Job&) = delete;

  // A job claimed from a durable store to be run here: `spec` re-admitted from the stored
  // request. Emits no accepted event (the store has it); its events are numbered from
  // `next_sequence` on, after those its watchers may have seen from an earlier run.
  static std::shared_ptr<Job> Resume(std::string id, JobSpec spec, bool bound_to_call,
                                     absl::Time create_time, int64_t next_sequence,
                                     MemoryBudget* budget);
  // A view of a stored job, which may run on another replica: `summary` is the job as GetJob
  // would answer it without result, `events` its kept events in order. Has no mesh, never runs.
  static std::shared_ptr<Job> Mirror(const v1::Job& summary, std::vector<v1::QuantizeEvent> events);
  // Takes over a newer stored state of a mirror and wakes its watchers; an older or equal one
  // (fewer events emitted, and no end where this one has none) is ignored, so that refreshes
  // may arrive in any order.
  void ApplyStored(const v1::Job& summary, std::vector<v1::QuantizeEvent> events);

  // Reports every later change to `sink`. Call before the job is shared with other threads.
  void SetEventSink(std::shared_ptr<JobEventSink> sink) { sink_ = std::move(sink); }

  const std::string& id() const { return id_; }
  const std::string& name() const { return name_; }
  const std::string& owner() const { return spec_.owner; }
  // The worker's view while it runs the job; the mesh is null once the job has ended.
  const JobSpec& spec() const { return spec_; }
  // The mesh while the job is queued or running, null once it has ended (or on a mirror): for
  // readers other than the worker (the web view's geometry), which may race with the job's end.
  std::shared_ptr<const TMesh> mesh() const;
  bool bound_to_call() const { return bound_to_call_; }
  const SolveInterrupter& interrupter() const { return interrupter_; }
  absl::Time create_time() const { return create_time_; }

  // ---- The worker that took the job from the queue ----

  // QUEUED -> RUNNING. False, changing nothing, if cancellation was requested meanwhile: the
  // worker then ends the job with FinishWithError.
  bool Start(absl::Time now);
  void PublishProgress(const v1::Progress& progress);
  void PublishIntermediate(v1::IntermediateQuantization intermediate);
  // The run returned a result: CANCELLED if it was interrupted on request, SUCCEEDED otherwise.
  void FinishWithResult(v1::QuantizationResult result, absl::Time now);
  // Ends the job without a result: CANCELLED if `status` is CANCELLED, FAILED otherwise.
  void FinishWithError(const absl::Status& status, absl::Time now);

  // ---- Anyone ----

  // Makes a queued job never start and asks a running solve to stop at its next check between
  // LP solves. Does not end a queued job by itself: whoever owns it (the canceller that took it
  // out of the queue, or the worker that popped it) ends it. Idempotent; no effect once done.
  void RequestCancel();
  // As RequestCancel, and the job then ends with the error `status` whatever its run returns:
  // this replica lost the job's lease in a shared store
  // (server/store/postgres/postgres_job_recorder.h), so what the run would report did not happen as
  // far as the store is concerned. The first status wins; no effect once done.
  void Abandon(const absl::Status& status);

  v1::JobState state() const;
  bool done() const;
  std::optional<absl::Time> end_time() const;
  v1::Job ToProto(v1::JobView view) const;

  // What a stream that has delivered every event numbered below `from` does next: write
  // `event`, or (when the job has ended and nothing numbered `from` or more is left) finish with
  // `final_status`: OK after a result, the error's status after an error. Neither: wait for the
  // next notification.
  struct StreamStep {
    std::optional<v1::QuantizeEvent> event;
    std::optional<absl::Status> final_status;
  };
  StreamStep NextForStream(int64_t from) const;

  // Adds a watcher, notified after every event until it expires. Notifies it once right away
  // if the job already has events, so that it cannot miss any.
  void AddWatcher(std::weak_ptr<JobWatcher> watcher);

 private:
  // Without the accepted event (Resume and Mirror add what the store has instead).
  Job(std::string id, JobSpec spec, std::string mesh_display_name, bool bound_to_call,
      absl::Time create_time, MemoryBudget* budget);

  v1::QuantizeEvent NewEvent(absl::Time now) const;
  // What an append leaves to do once the lock is released: record the event, wake watchers.
  struct Appended {
    std::vector<std::shared_ptr<JobWatcher>> watchers;
    std::optional<v1::QuantizeEvent> to_record;  // set when the job has a sink
  };
  Appended AppendLocked(v1::QuantizeEvent event) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  std::vector<std::shared_ptr<JobWatcher>> LiveWatchersLocked()
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Deliver(Appended appended);
  static void Notify(const std::vector<std::shared_ptr<JobWatcher>>& watchers);

  // Ends the job: state, end time, the terminal event, and the mesh let go.
  Appended EndLocked(v1::JobState state, absl::Time now, v1::QuantizeEvent terminal)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  // Ends the job with the error `status`: CANCELLED if it is CANCELLED, FAILED otherwise.
  Appended EndWithErrorLocked(const absl::Status& status, absl::Time now)
      ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  const std::string id_;
  const std::string name_;
  // Written once more after construction, by EndLocked, when no worker reads it any more.
  JobSpec spec_;
  std::string mesh_display_name_;  // set by the constructors, read-only after
  const bool bound_to_call_;
  const absl::Time create_time_;
  MemoryBudget* const budget_;
  SolveInterrupter interrupter_;
  std::shared_ptr<JobEventSink> sink_;  // set before the job is shared, read-only after

  mutable absl::Mutex mutex_;
  v1::JobState state_ ABSL_GUARDED_BY(mutex_) = v1::QUEUED;
  bool cancel_requested_ ABSL_GUARDED_BY(mutex_) = false;
  std::optional<absl::Status> abandoned_ ABSL_GUARDED_BY(mutex_);  // see Abandon
  std::optional<absl::Time> start_time_ ABSL_GUARDED_BY(mutex_);
  std::optional<absl::Time> end_time_ ABSL_GUARDED_BY(mutex_);
  std::optional<v1::Progress> latest_progress_ ABSL_GUARDED_BY(mutex_);
  JobEventLog events_ ABSL_GUARDED_BY(mutex_);
  std::vector<std::weak_ptr<JobWatcher>> watchers_ ABSL_GUARDED_BY(mutex_);
  MemoryReservation retained_memory_ ABSL_GUARDED_BY(mutex_);  // from the end on
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MODEL_JOB_H_
