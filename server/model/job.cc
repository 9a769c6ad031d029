// SPDX-License-Identifier: Apache-2.0
#include "server/model/job.h"

#include <utility>

#include "core/invariant.h"
#include "google/protobuf/util/time_util.h"
#include "server/memory/memory_estimates.h"
#include "server/model/resource_names.h"

namespace ispq::server {
namespace {

google::protobuf::Timestamp ToTimestamp(absl::Time time) {
  return google::protobuf::util::TimeUtil::NanosecondsToTimestamp(absl::ToUnixNanos(time));
}

absl::Time FromTimestamp(const google::protobuf::Timestamp& timestamp) {
  return absl::FromUnixNanos(google::protobuf::util::TimeUtil::TimestampToNanoseconds(timestamp));
}

// The descriptive part of a stored job's spec, for a mirror, which has no mesh.
JobSpec MirrorSpec(const v1::Job& summary) {
  JobSpec spec;
  spec.mesh_stats = summary.mesh_stats();
  spec.stored_mesh = summary.stored_mesh();
  spec.requested_options = summary.options();
  spec.options.scaling = summary.scaling();
  spec.owner = summary.owner();
  spec.request_id = summary.request_id();
  return spec;
}

}  // namespace

Job::Job(std::string id, JobSpec spec, std::string mesh_display_name, bool bound_to_call,
         absl::Time create_time, MemoryBudget* budget)
    : id_(std::move(id)),
      name_(ResourceName(kJobCollection, id_)),
      spec_(std::move(spec)),
      mesh_display_name_(std::move(mesh_display_name)),
      bound_to_call_(bound_to_call),
      create_time_(create_time),
      budget_(budget) {}

Job::Job(std::string id, JobSpec spec, bool bound_to_call, int queue_position, absl::Time now,
         MemoryBudget* budget)
    : Job(std::move(id), std::move(spec), std::string(), bound_to_call, now, budget) {
  mesh_display_name_ = spec_.mesh->name();
  v1::QuantizeEvent event = NewEvent(now);
  v1::JobAccepted* accepted = event.mutable_accepted();
  *accepted->mutable_mesh_stats() = spec_.mesh_stats;
  accepted->set_mesh_display_name(mesh_display_name_);
  accepted->set_queue_position(queue_position);
  accepted->set_scaling(spec_.options.scaling);
  absl::MutexLock lock(&mutex_);
  events_.Append(std::move(event));  // no watcher or sink can exist yet
}

std::shared_ptr<Job> Job::Resume(std::string id, JobSpec spec, bool bound_to_call,
                                 absl::Time create_time, int64_t next_sequence,
                                 MemoryBudget* budget) {
  std::string display_name = spec.mesh->name();
  std::shared_ptr<Job> job(new Job(std::move(id), std::move(spec), std::move(display_name),
                                   bound_to_call, create_time, budget));
  absl::MutexLock lock(&job->mutex_);
  job->events_.ContinueFrom(next_sequence);
  return job;
}

std::shared_ptr<Job> Job::Mirror(const v1::Job& summary, std::vector<v1::QuantizeEvent> events) {
  absl::StatusOr<std::string> id = ParseResourceName(kJobCollection, summary.name());
  std::shared_ptr<Job> job(new Job(id.ok() ? *id : summary.name(), MirrorSpec(summary),
                                   summary.mesh_display_name(), summary.bound_to_call(),
                                   FromTimestamp(summary.create_time()), /*budget=*/nullptr));
  job->ApplyStored(summary, std::move(events));
  return job;
}

void Job::ApplyStored(const v1::Job& summary, std::vector<v1::QuantizeEvent> events) {
  std::vector<std::shared_ptr<JobWatcher>> watchers;
  {
    absl::MutexLock lock(&mutex_);
    const bool newer = summary.event_count() > events_.emitted() ||
                       (summary.done() && !end_time_.has_value()) ||
                       (summary.state() != state_ && !end_time_.has_value() &&
                        summary.event_count() == events_.emitted());
    if (!newer) return;
    state_ = summary.state();
    if (summary.has_start_time()) start_time_ = FromTimestamp(summary.start_time());
    if (summary.done()) end_time_ = FromTimestamp(summary.end_time());
    if (summary.has_latest_progress()) latest_progress_ = summary.latest_progress();
    events_.Restore(std::move(events), summary.event_count());
    watchers = LiveWatchersLocked();
  }
  Notify(watchers);
}

v1::QuantizeEvent Job::NewEvent(absl::Time now) const {
  v1::QuantizeEvent event;
  event.set_job(name_);
  *event.mutable_time() = ToTimestamp(now);
  return event;
}

Job::Appended Job::AppendLocked(v1::QuantizeEvent event) {
  const int64_t sequence = events_.Append(std::move(event));
  Appended appended;
  if (sink_ != nullptr) appended.to_record = *events_.FirstAtOrAfter(sequence);
  appended.watchers = LiveWatchersLocked();
  return appended;
}

void Job::Deliver(Appended appended) {
  if (appended.to_record.has_value()) sink_->Record(*this, &*appended.to_record);
  Notify(appended.watchers);
}

std::vector<std::shared_ptr<JobWatcher>> Job::LiveWatchersLocked() {
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

Job::Appended Job::EndLocked(v1::JobState state, absl::Time now, v1::QuantizeEvent terminal) {
  ISPQ_INVARIANT(!end_time_.has_value(), "a job ends once");
  ISPQ_INVARIANT(state_ == v1::QUEUED || state_ == v1::RUNNING, "only a live job ends");
  ISPQ_INVARIANT(state == v1::SUCCEEDED || state == v1::FAILED || state == v1::CANCELLED,
                 "a job ends in a terminal state");
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
  {
    absl::MutexLock lock(&mutex_);
    if (cancel_requested_ || state_ != v1::QUEUED) return false;
    ISPQ_INVARIANT(!end_time_.has_value(), "a queued job has not ended");
    state_ = v1::RUNNING;
    start_time_ = now;
  }
  if (sink_ != nullptr) sink_->Record(*this, nullptr);
  return true;
}

void Job::PublishProgress(const v1::Progress& progress) {
  v1::QuantizeEvent event = NewEvent(absl::Now());
  *event.mutable_progress() = progress;
  Appended appended;
  {
    absl::MutexLock lock(&mutex_);
    latest_progress_ = progress;
    appended = AppendLocked(std::move(event));
  }
  Deliver(std::move(appended));
}

void Job::PublishIntermediate(v1::IntermediateQuantization intermediate) {
  v1::QuantizeEvent event = NewEvent(absl::Now());
  *event.mutable_intermediate() = std::move(intermediate);
  Appended appended;
  {
    absl::MutexLock lock(&mutex_);
    appended = AppendLocked(std::move(event));
  }
  Deliver(std::move(appended));
}

void Job::FinishWithResult(v1::QuantizationResult result, absl::Time now) {
  const bool interrupted = result.termination() == v1::INTERRUPTED;
  v1::QuantizeEvent event = NewEvent(now);
  *event.mutable_result() = std::move(result);
  Appended appended;
  {
    absl::MutexLock lock(&mutex_);
    if (end_time_.has_value()) return;
    if (abandoned_.has_value()) {
      appended = EndWithErrorLocked(*abandoned_, now);
    } else {
      appended = EndLocked(interrupted && cancel_requested_ ? v1::CANCELLED : v1::SUCCEEDED, now,
                           std::move(event));
    }
  }
  Deliver(std::move(appended));
}

void Job::FinishWithError(const absl::Status& status, absl::Time now) {
  Appended appended;
  {
    absl::MutexLock lock(&mutex_);
    if (end_time_.has_value()) return;
    appended = EndWithErrorLocked(abandoned_.value_or(status), now);
  }
  Deliver(std::move(appended));
}

Job::Appended Job::EndWithErrorLocked(const absl::Status& status, absl::Time now) {
  v1::QuantizeEvent event = NewEvent(now);
  event.mutable_error()->set_code(static_cast<int32_t>(status.code()));
  event.mutable_error()->set_message(std::string(status.message()));
  return EndLocked(absl::IsCancelled(status) ? v1::CANCELLED : v1::FAILED, now, std::move(event));
}

void Job::RequestCancel() {
  absl::MutexLock lock(&mutex_);
  if (end_time_.has_value()) return;
  cancel_requested_ = true;
  interrupter_.Interrupt();
}

void Job::Abandon(const absl::Status& status) {
  absl::MutexLock lock(&mutex_);
  if (end_time_.has_value()) return;
  if (!abandoned_.has_value()) abandoned_ = status;
  cancel_requested_ = true;
  interrupter_.Interrupt();
}

std::shared_ptr<const TMesh> Job::mesh() const {
  absl::MutexLock lock(&mutex_);
  return spec_.mesh;
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
