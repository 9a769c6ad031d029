// SPDX-License-Identifier: Apache-2.0
// Streams one job's events to one client: the reactor behind both Quantize and WatchJob
// (raw methods, see server/grpc/raw_proto_call.h: events are serialized here).
//
// It writes one event at a time (flow control: a slow client holds one event in flight, and
// the job's compacted log means it catches up with the newest snapshot instead of a backlog),
// is woken by the job after each new event (JobWatcher) and by gRPC after each write, and ends
// the call with the job's status after the terminal event. For Quantize the job belongs to the
// call: when the client cancels, disconnects or passes its deadline, the job is cancelled too.
//
// A Quantize stream exists before its job: the call is answered at once while its request is
// admitted off gRPC's threads (server/admission/admission_pool.h), and the job is attached (or the
// call rejected) when admission ends. The call is not finished before then, even when the client
// cancels it, because admission still uses the call's context; a call that ended during
// admission cancels its job as soon as it is attached.
//
// Lifetime: the stream owns itself from Create until gRPC's OnDone; the job holds it weakly, so
// a notification racing with the end of the call keeps it alive just long enough to see that it
// is finished. Every decision is taken under the stream's mutex and every gRPC operation is
// started after releasing it, so a reaction that gRPC runs inline cannot deadlock. The event in
// flight is accounted in the memory budget as a response.
#ifndef ISPQ_SERVER_GRPC_JOB_EVENT_STREAM_H_
#define ISPQ_SERVER_GRPC_JOB_EVENT_STREAM_H_

#include <cstdint>
#include <memory>
#include <optional>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "grpcpp/support/byte_buffer.h"
#include "grpcpp/support/server_callback.h"
#include "ispq/v1/service.pb.h"
#include "server/jobs/job_scheduler.h"
#include "server/memory/memory_budget.h"
#include "server/model/job.h"

namespace ispq::server {

class JobEventStream : public grpc::ServerWriteReactor<grpc::ByteBuffer>,
                       public JobWatcher,
                       public std::enable_shared_from_this<JobEventStream> {
 public:
  // A stream without a job yet; the returned pointer is also the reactor for gRPC. With
  // `cancel_job_with_call` set, the call's end before the job's cancels the job through it.
  // `budget` (may be null) accounts for the event in flight.
  static std::shared_ptr<JobEventStream> Create(JobScheduler* cancel_job_with_call,
                                                MemoryBudget* budget);
  // Create and Attach in one, for a job that exists.
  static grpc::ServerWriteReactor<grpc::ByteBuffer>* Start(std::shared_ptr<Job> job,
                                                           int64_t from_event,
                                                           JobScheduler* cancel_job_with_call,
                                                           MemoryBudget* budget);

  JobEventStream(JobScheduler* cancel_job_with_call, MemoryBudget* budget);

  // Streams `job` from event `from_event`. Call once, or Reject instead.
  void Attach(std::shared_ptr<Job> job, int64_t from_event);
  // Ends the call with `status` before any event (a refused request).
  void Reject(grpc::Status status);

  void OnJobEvent() override { Advance(); }
  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  // Starts the next write or the finish, if one is due and none is in flight.
  void Advance();

  JobScheduler* const cancel_job_with_call_;
  MemoryBudget* const budget_;
  std::shared_ptr<JobEventStream> self_;  // set by Create, released by OnDone

  absl::Mutex mutex_;
  std::shared_ptr<Job> job_ ABSL_GUARDED_BY(mutex_);  // null until attached
  bool admitted_ ABSL_GUARDED_BY(mutex_) = false;     // Attach or Reject was called
  std::optional<grpc::Status> rejection_ ABSL_GUARDED_BY(mutex_);
  int64_t next_sequence_ ABSL_GUARDED_BY(mutex_) = 0;
  grpc::ByteBuffer in_flight_ ABSL_GUARDED_BY(mutex_);  // gRPC reads it until OnWriteDone
  MemoryReservation in_flight_memory_ ABSL_GUARDED_BY(mutex_);
  bool write_in_flight_ ABSL_GUARDED_BY(mutex_) = false;
  bool call_broken_ ABSL_GUARDED_BY(mutex_) = false;  // cancelled or a write failed
  bool finished_ ABSL_GUARDED_BY(mutex_) = false;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_JOB_EVENT_STREAM_H_
