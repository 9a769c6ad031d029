#include "server/job.h"

#include <utility>

#include "google/protobuf/util/time_util.h"
#include "server/job_memory.h"
#include "server/resource_names.h"

namespace ispq::server {
namespace {

google::protobuf::Timestamp ToTimestamp(absl::Time time) {
  return google::protobuf::util::TimeUtil::NanosecondsToTimestamp(absl::ToUnixNanos(time));
}

}  // namespace

Job::Job(std::string id, JobSpec spec, bool bound_to_call, int queue_position, absl::Time now,
         MemoryBudget* budget)
    : id_(std::move(id)),
      name_(ResourceName(kJobCollection, id_)),
      spec_(std::move(spec)),
      mesh_display_name_(spec_.mesh->name()),
      bound_to_call_(bound_to_call),
      create_time_(now),
      budget_(budget) {
  v1::QuantizeEvent event = NewEvent(now);
  v1::JobAccepted* accepted = event.mutable_accepted();
  *accepted->mutable_mesh_stats() = spec_.mesh_stats;
  accepted->set_mesh_display_name(mesh_display_name_);
  accepted->set_queue_position(queue_position);
  accepted->set_scaling(spec_.options.scaling);
  absl::MutexLock lock(&mutex_);
  events_.Append(std::move(event));  // no watcher can exist yet
}

v1::QuantizeEvent Job::NewEvent(absl::Time now) const {
  v1::QuantizeEvent event;
  event.set_job(name_);
  *event.mutable_time() = ToTimestamp(now);
  return event;
}

std::vector<std::shared_ptr<JobWatcher>> Job::AppendLocked(v1::QuantizeEvent event) {
  events_.Append(std::move(event));
  std::vector<std::shared_ptr<JobWatcher>> live;
  live.reserve(watchers_.size());
  std::erase_if(watchers_, [&live](const std::weak_ptr<JobWatcher>& weak) {
    std::shared_ptr<JobWatcher> watcher = weak.lock();
    if (watcher == nullptr) return true;
    live.push_back(std::move(watcher));
    return false;
  });
  return live;
}

std::vector<std::shared_ptr<JobWatcher>> Job::EndLocked(v1::JobState state, absl::Time now,
                                                        v1::QuantizeEvent terminal) {
  state_ = state;
  end_time_ = now;
  if (budget_ != nullptr) {
    // What the job keeps from now on; it must be kept whatever the budget says.
    retained_memory_ = budget_->ForceReserve(
        MemoryUse::kResults,
        RetainedJobBytes(terminal.has_result() ? &terminal.result() : nullptr));
  }
  spec_.mesh.reset();
  spec_.memory.Release();
  return AppendLocked(std::move(terminal));
}

void Job::Notify(const std::vector<std::shared_ptr<JobWatcher>>& watchers) {
  for (const std::shared_ptr<JobWatcher>& watcher : watchers) watcher->OnJobEvent();
}

bool Job::Start(absl::Time now) {
  absl::MutexLock lock(&mutex_);
  if (cancel_requested_ || state_ != v1::QUEUED) return false;
  state_ = v1::RUNNING;
  start_time_ = now;
  return true;
}

void Job::PublishProgress(const v1::Progress& progress) {
  v1::QuantizeEvent event = NewEvent(absl::Now());
  *event.mutable_progress() = progress;
  std::vector<std::shared_ptr<JobWatcher>> watchers;
  {
    absl::MutexLock lock(&mutex_);
    latest_progress_ = progress;
    watchers = AppendLocked(std::move(event));
  }
  Notify(watchers);
}

void Job::PublishIntermediate(v1::IntermediateQuantization intermediate) {
  v1::QuantizeEvent event = NewEvent(absl::Now());
  *event.mutable_intermediate() = std::move(intermediate);
  std::vector<std::shared_ptr<JobWatcher>> watchers;
  {
    absl::MutexLock lock(&mutex_);
    watchers = AppendLocked(std::move(event));
  }
  Notify(watchers);
}

void Job::FinishWithResult(v1::QuantizationResult result, absl::Time now) {
  const bool interrupted = result.termination() == v1::INTERRUPTED;
  v1::QuantizeEvent event = NewEvent(now);
  *event.mutable_result() = std::move(result);
  std::vector<std::shared_ptr<JobWatcher>> watchers;
  {
    absl::MutexLock lock(&mutex_);
    if (end_time_.has_value()) return;
    watchers = EndLocked(interrupted && cancel_requested_ ? v1::CANCELLED : v1::SUCCEEDED, now,
                         std::move(event));
  }
  Notify(watchers);
}

void Job::FinishWithError(const absl::Status& status, absl::Time now) {
  v1::QuantizeEvent event = NewEvent(now);
  event.mutable_error()->set_code(static_cast<int32_t>(status.code()));
  event.mutable_error()->set_message(std::string(status.message()));
  std::vector<std::shared_ptr<JobWatcher>> watchers;
  {
    absl::MutexLock lock(&mutex_);
    if (end_time_.has_value()) return;
    watchers =
        EndLocked(absl::IsCancelled(status) ? v1::CANCELLED : v1::FAILED, now, std::move(event));
  }
  Notify(watchers);
}

void Job::RequestCancel() {
  absl::MutexLock lock(&mutex_);
  if (end_time_.has_value()) return;
  cancel_requested_ = true;
  interrupter_.Interrupt();
}

v1::JobState Job::state() const {
  absl::MutexLock lock(&mutex_);
  return state_;
}

bool Job::done() const {
  absl::MutexLock lock(&mutex_);
  return end_time_.has_value();
}

std::optional<absl::Time> Job::end_time() const {
  absl::MutexLock lock(&mutex_);
  return end_time_;
}

v1::Job Job::ToProto(v1::JobView view) const {
  v1::Job proto;
  proto.set_name(name_);
  *proto.mutable_create_time() = ToTimestamp(create_time_);
  proto.set_mesh_display_name(mesh_display_name_);
  *proto.mutable_mesh_stats() = spec_.mesh_stats;
  proto.set_stored_mesh(spec_.stored_mesh);
  *proto.mutable_options() = spec_.requested_options;
  proto.set_scaling(spec_.options.scaling);
  proto.set_bound_to_call(bound_to_call_);
  proto.set_owner(spec_.owner);
  proto.set_request_id(spec_.request_id);
  absl::MutexLock lock(&mutex_);
  proto.set_state(state_);
  proto.set_done(end_time_.has_value());
  if (start_time_.has_value()) *proto.mutable_start_time() = ToTimestamp(*start_time_);
  if (end_time_.has_value()) *proto.mutable_end_time() = ToTimestamp(*end_time_);
  if (latest_progress_.has_value()) *proto.mutable_latest_progress() = *latest_progress_;
  proto.set_event_count(events_.emitted());
  if (events_.ended()) {
    const v1::QuantizeEvent& terminal = *events_.FirstAtOrAfter(events_.emitted() - 1);
    if (terminal.has_result()) {
      v1::QuantizationResult* result = proto.mutable_result();
      *result = terminal.result();
      if (view == v1::BASIC) {
        result->clear_q();
        result->clear_stats();
      }
    } else {
      *proto.mutable_error() = terminal.error();
    }
  }
  return proto;
}

Job::StreamStep Job::NextForStream(int64_t from) const {
  StreamStep step;
  absl::MutexLock lock(&mutex_);
  if (const v1::QuantizeEvent* event = events_.FirstAtOrAfter(from); event != nullptr) {
    step.event = *event;
    return step;
  }
  if (events_.ended()) {
    const v1::QuantizeEvent& terminal = *events_.FirstAtOrAfter(events_.emitted() - 1);
    step.final_status = terminal.has_result()
                            ? absl::OkStatus()
                            : absl::Status(static_cast<absl::StatusCode>(terminal.error().code()),
                                           terminal.error().message());
  }
  return step;
}

void Job::AddWatcher(std::weak_ptr<JobWatcher> watcher) {
  {
    absl::MutexLock lock(&mutex_);
    // An ended job emits nothing more: its watchers need the one notification below only. A
    // running job drops expired watchers here too, so repeated watching cannot grow the list.
    std::erase_if(watchers_, [](const std::weak_ptr<JobWatcher>& w) { return w.expired(); });
    if (!end_time_.has_value()) watchers_.push_back(watcher);
  }
  if (std::shared_ptr<JobWatcher> live = watcher.lock()) live->OnJobEvent();
}

}  // namespace ispq::server
