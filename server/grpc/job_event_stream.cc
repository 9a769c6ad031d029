// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/job_event_stream.h"

#include <utility>

#include "server/grpc/grpc_status.h"
#include "server/grpc/raw_proto_call.h"

namespace ispq::server {

std::shared_ptr<JobEventStream> JobEventStream::Create(JobScheduler* cancel_job_with_call,
                                                       MemoryBudget* budget) {
  auto stream = std::make_shared<JobEventStream>(cancel_job_with_call, budget);
  stream->self_ = stream;
  return stream;
}

grpc::ServerWriteReactor<grpc::ByteBuffer>* JobEventStream::Start(
    std::shared_ptr<Job> job, int64_t from_event, JobScheduler* cancel_job_with_call,
    MemoryBudget* budget) {
  std::shared_ptr<JobEventStream> stream = Create(cancel_job_with_call, budget);
  stream->Attach(std::move(job), from_event);
  return stream.get();
}

JobEventStream::JobEventStream(JobScheduler* cancel_job_with_call, MemoryBudget* budget)
    : cancel_job_with_call_(cancel_job_with_call), budget_(budget) {}

void JobEventStream::Attach(std::shared_ptr<Job> job, int64_t from_event) {
  bool call_over = false;
  {
    absl::MutexLock lock(&mutex_);
    admitted_ = true;
    call_over = call_broken_;
    if (!call_over) {
      job_ = job;
      next_sequence_ = from_event;
    }
  }
  if (call_over) {
    // The call ended during admission (deadline, cancel): its job must not outlive it.
    if (cancel_job_with_call_ != nullptr) cancel_job_with_call_->Cancel(*job);
    Advance();
    return;
  }
  // AddWatcher notifies once at once: the stream writes whatever is there already.
  job->AddWatcher(weak_from_this());
}

void JobEventStream::Reject(grpc::Status status) {
  {
    absl::MutexLock lock(&mutex_);
    admitted_ = true;
    rejection_ = std::move(status);
  }
  Advance();
}

void JobEventStream::OnWriteDone(bool ok) {
  {
    absl::MutexLock lock(&mutex_);
    write_in_flight_ = false;
    in_flight_.Clear();  // gRPC is done with it
    in_flight_memory_.Release();
    if (!ok) call_broken_ = true;
  }
  Advance();
}

void JobEventStream::OnCancel() {
  std::shared_ptr<Job> job;
  {
    absl::MutexLock lock(&mutex_);
    call_broken_ = true;
    job = job_;
  }
  // Outside the stream's mutex: cancelling emits the job's terminal event, which notifies us.
  if (cancel_job_with_call_ != nullptr && job != nullptr) cancel_job_with_call_->Cancel(*job);
  Advance();
}

void JobEventStream::OnDone() {
  // The last reaction: let go of ourselves. A notification in progress may still hold a
  // reference; the stream is destroyed when it returns.
  std::shared_ptr<JobEventStream> keep_until_return = std::move(self_);
}

void JobEventStream::Advance() {
  const grpc::ByteBuffer* to_write = nullptr;
  std::optional<grpc::Status> to_finish;
  {
    absl::MutexLock lock(&mutex_);
    // Until admission has decided, the call stays open even if cancelled: admission still uses
    // its context, which lives until the call is done.
    if (finished_ || write_in_flight_ || !admitted_) return;
    if (call_broken_) {
      to_finish = grpc::Status(grpc::StatusCode::CANCELLED, "the call was cancelled");
    } else if (rejection_.has_value()) {
      to_finish = *rejection_;
    } else {
      Job::StreamStep step = job_->NextForStream(next_sequence_);
      if (step.event.has_value()) {
        next_sequence_ = step.event->sequence() + 1;
        const grpc::Status serialized = SerializeMessage(*step.event, in_flight_);
        if (serialized.ok()) {
          write_in_flight_ = true;
          to_write = &in_flight_;
          if (budget_ != nullptr) {
            in_flight_memory_ = budget_->ForceReserve(MemoryUse::kResponses, in_flight_.Length());
          }
        } else {
          to_finish = serialized;
        }
      } else if (step.final_status.has_value()) {
        to_finish = ToGrpcStatus(*step.final_status);
      }
    }
    if (to_finish.has_value()) finished_ = true;
  }
  if (to_write != nullptr) StartWrite(to_write);
  if (to_finish.has_value()) Finish(*std::move(to_finish));
}

}  // namespace ispq::server
