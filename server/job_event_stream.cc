#include "server/job_event_stream.h"

#include <optional>
#include <utility>

#include "server/grpc_status.h"
#include "server/raw_proto_call.h"

namespace ispq::server {

grpc::ServerWriteReactor<grpc::ByteBuffer>* JobEventStream::Start(
    std::shared_ptr<Job> job, int64_t from_event, JobScheduler* cancel_job_with_call) {
  auto stream = std::make_shared<JobEventStream>(job, from_event, cancel_job_with_call);
  stream->self_ = stream;
  // AddWatcher notifies once at once: the stream writes whatever is there already.
  job->AddWatcher(stream);
  return stream.get();
}

JobEventStream::JobEventStream(std::shared_ptr<Job> job, int64_t from_event,
                               JobScheduler* cancel_job_with_call)
    : job_(std::move(job)),
      cancel_job_with_call_(cancel_job_with_call),
      next_sequence_(from_event) {}

void JobEventStream::OnWriteDone(bool ok) {
  {
    absl::MutexLock lock(&mutex_);
    write_in_flight_ = false;
    if (!ok) call_broken_ = true;
  }
  Advance();
}

void JobEventStream::OnCancel() {
  {
    absl::MutexLock lock(&mutex_);
    call_broken_ = true;
  }
  // Outside the stream's mutex: cancelling emits the job's terminal event, which notifies us.
  if (cancel_job_with_call_ != nullptr) cancel_job_with_call_->Cancel(*job_);
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
    if (finished_ || write_in_flight_) return;
    if (call_broken_) {
      to_finish = grpc::Status(grpc::StatusCode::CANCELLED, "the call was cancelled");
    } else {
      Job::StreamStep step = job_->NextForStream(next_sequence_);
      if (step.event.has_value()) {
        next_sequence_ = step.event->sequence() + 1;
        const grpc::Status serialized = SerializeMessage(*step.event, in_flight_);
        if (serialized.ok()) {
          write_in_flight_ = true;
          to_write = &in_flight_;
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
