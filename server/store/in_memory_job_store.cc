// SPDX-License-Identifier: Apache-2.0
#include "server/store/in_memory_job_store.h"

#include <algorithm>
#include <optional>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace ispq::server {
namespace {

constexpr int kDefaultPageSize = 50;
constexpr int kMaxPageSize = 1000;

}  // namespace

InMemoryJobStore::InMemoryJobStore(RetentionPolicy policy) : policy_(policy) {}

absl::StatusOr<std::shared_ptr<Job>> InMemoryJobStore::Add(std::shared_ptr<Job> job,
                                                           const std::string& /*request*/,
                                                           absl::Time now) {
  absl::MutexLock lock(&mutex_);
  PruneLocked(now);
  const uint64_t ordinal = next_ordinal_++;
  ordinal_by_id_[job->id()] = ordinal;
  by_ordinal_[ordinal] = job;
  return job;
}

void InMemoryJobStore::Cancel(Job& job, absl::Time /*now*/) { job.RequestCancel(); }

std::shared_ptr<Job> InMemoryJobStore::Find(const std::string& id, absl::Time now) {
  absl::MutexLock lock(&mutex_);
  PruneLocked(now);
  const auto it = ordinal_by_id_.find(id);
  return it == ordinal_by_id_.end() ? nullptr : by_ordinal_.at(it->second);
}

absl::StatusOr<JobStore::Page> InMemoryJobStore::List(const Query& query, absl::Time now) {
  if (query.page_size < 0) {
    return absl::InvalidArgumentError(absl::StrCat("page_size ", query.page_size, " is negative"));
  }
  const int size =
      query.page_size == 0 ? kDefaultPageSize : std::min(query.page_size, kMaxPageSize);
  // The token is the ordinal of the next job to list: listing resumes below it.
  uint64_t start = UINT64_MAX;
  if (!query.page_token.empty() && !absl::SimpleAtoi(query.page_token, &start)) {
    return absl::InvalidArgumentError("page_token is not one this server issued");
  }
  Page page;
  absl::MutexLock lock(&mutex_);
  PruneLocked(now);
  for (auto it = std::make_reverse_iterator(by_ordinal_.upper_bound(start));
       it != by_ordinal_.rend(); ++it) {
    const Job& job = *it->second;
    if (query.state != v1::JOB_STATE_UNSPECIFIED && job.state() != query.state) continue;
    if (query.visible && !query.visible(job)) continue;
    if (static_cast<int>(page.jobs.size()) == size) {
      page.next_page_token = absl::StrCat(it->first);
      break;
    }
    page.jobs.push_back({it->second, absl::StrCat(it->first)});
  }
  return page;
}

bool InMemoryJobStore::EvictOldestFinished() {
  std::shared_ptr<Job> evicted;  // destroyed after the lock is released
  absl::MutexLock lock(&mutex_);
  std::optional<std::pair<absl::Time, uint64_t>> oldest;
  for (const auto& [ordinal, job] : by_ordinal_) {
    if (std::optional<absl::Time> end = job->end_time(); end.has_value()) {
      oldest =
          std::min(oldest.value_or(std::make_pair(*end, ordinal)), std::make_pair(*end, ordinal));
    }
  }
  if (!oldest.has_value()) return false;
  const auto it = by_ordinal_.find(oldest->second);
  evicted = std::move(it->second);
  ordinal_by_id_.erase(evicted->id());
  by_ordinal_.erase(it);
  return true;
}

std::vector<std::shared_ptr<Job>> InMemoryJobStore::ActiveJobs() const {
  std::vector<std::shared_ptr<Job>> active;
  absl::MutexLock lock(&mutex_);
  for (const auto& [ordinal, job] : by_ordinal_) {
    if (!job->done()) active.push_back(job);
  }
  return active;
}

v1::JobCounts InMemoryJobStore::CountByState() const {
  v1::JobCounts counts;
  absl::MutexLock lock(&mutex_);
  for (const auto& [ordinal, job] : by_ordinal_) {
    switch (job->state()) {
      case v1::QUEUED:
        counts.set_queued(counts.queued() + 1);
        break;
      case v1::RUNNING:
        counts.set_running(counts.running() + 1);
        break;
      case v1::SUCCEEDED:
        counts.set_succeeded(counts.succeeded() + 1);
        break;
      case v1::FAILED:
        counts.set_failed(counts.failed() + 1);
        break;
      case v1::CANCELLED:
        counts.set_cancelled(counts.cancelled() + 1);
        break;
      default:
        break;
    }
  }
  return counts;
}

void InMemoryJobStore::PruneLocked(absl::Time now) {
  // Finished jobs by end time, oldest first.
  std::vector<std::pair<absl::Time, uint64_t>> finished;
  for (const auto& [ordinal, job] : by_ordinal_) {
    if (std::optional<absl::Time> end = job->end_time(); end.has_value()) {
      finished.emplace_back(*end, ordinal);
    }
  }
  std::sort(finished.begin(), finished.end());
  const size_t over_count = finished.size() > static_cast<size_t>(policy_.max_finished)
                                ? finished.size() - static_cast<size_t>(policy_.max_finished)
                                : 0;
  for (size_t i = 0; i < finished.size(); ++i) {
    const bool expired = now - finished[i].first > policy_.max_age;
    if (i >= over_count && !expired) break;  // sorted: every later one is newer
    const auto it = by_ordinal_.find(finished[i].second);
    ordinal_by_id_.erase(it->second->id());
    by_ordinal_.erase(it);
  }
}

}  // namespace ispq::server
