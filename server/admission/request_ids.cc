// SPDX-License-Identifier: Apache-2.0
#include "server/admission/request_ids.h"

#include <algorithm>
#include <utility>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"

namespace ispq::server {
namespace {

constexpr size_t kMaxRequestIdLength = 64;

// principal and id in one key; the separator cannot occur in an id.
std::string KeyOf(const std::string& principal, const std::string& request_id) {
  return absl::StrCat(request_id, "/", principal);
}

absl::Status DifferentRequest(const std::string& request_id) {
  return absl::AlreadyExistsError(
      absl::StrCat("request_id ", request_id, " was already used for a different request"));
}

}  // namespace

absl::Status ValidateRequestId(const std::string& request_id) {
  const bool well_formed = !request_id.empty() && request_id.size() <= kMaxRequestIdLength &&
                           std::all_of(request_id.begin(), request_id.end(), [](char c) {
                             return absl::ascii_isalnum(c) || c == '-' || c == '_';
                           });
  if (well_formed) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat("request_id must be 1-", kMaxRequestIdLength,
                                                 " characters of [A-Za-z0-9_-] (a UUID), got ",
                                                 request_id.size(), " characters"));
}

RequestIds::RequestIds(JobFinder find_job) : find_job_(std::move(find_job)) {}

RequestIds::Decision RequestIds::Begin(const std::string& principal, const std::string& request_id,
                                       std::string fingerprint, Waiter waiter) {
  Decision decision;
  const std::string key = KeyOf(principal, request_id);
  absl::MutexLock lock(&mutex_);
  auto it = entries_.find(key);
  if (it != entries_.end() && it->second.job_id.has_value()) {
    std::shared_ptr<Job> job = find_job_(*it->second.job_id);
    if (job == nullptr) {
      entries_.erase(it);  // the job is no longer retained: the id is free again
      it = entries_.end();
    } else if (it->second.fingerprint != fingerprint) {
      decision.outcome = DifferentRequest(request_id);
      return decision;
    } else {
      decision.outcome = std::move(job);
      return decision;
    }
  }
  if (it != entries_.end()) {  // the first call is being admitted
    if (it->second.fingerprint != fingerprint) {
      decision.outcome = DifferentRequest(request_id);
    } else {
      it->second.waiters.push_back(std::move(waiter));
    }
    return decision;
  }
  SweepLocked();
  Entry entry;
  entry.fingerprint = std::move(fingerprint);
  entries_.emplace(key, std::move(entry));
  decision.ticket = Ticket{key};
  return decision;
}

void RequestIds::Complete(const Ticket& ticket, const Outcome& outcome) {
  std::vector<Waiter> waiters;
  {
    absl::MutexLock lock(&mutex_);
    const auto it = entries_.find(ticket.key);
    if (it == entries_.end()) return;
    waiters = std::move(it->second.waiters);
    if (outcome.ok()) {
      it->second.job_id = (*outcome)->id();
      it->second.waiters.clear();
    } else {
      entries_.erase(it);
    }
  }
  for (Waiter& waiter : waiters) std::move(waiter)(outcome);
}

void RequestIds::SweepLocked() {
  if (entries_.size() < sweep_at_) return;
  absl::erase_if(entries_, [this](const auto& entry) {
    return entry.second.job_id.has_value() && find_job_(*entry.second.job_id) == nullptr;
  });
  sweep_at_ = std::max<size_t>(1024, 2 * entries_.size());
}

}  // namespace ispq::server
