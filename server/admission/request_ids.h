// SPDX-License-Identifier: Apache-2.0
// Idempotent SubmitJob (AIP-155): which job each principal's request_id created, so that a
// retried call returns that job instead of creating a duplicate.
//
// An id is claimed before its request is admitted, so that a retry arriving while the first call
// is still being parsed and validated (its deadline passed and the client retried at once) waits
// for the first call's outcome instead of racing it to create a second job. If the first call
// fails, its waiters get its error and the id is free again (a later retry is a new attempt). An
// id with a different request fingerprint (server/admission/request_fingerprint.h) is
// ALREADY_EXISTS. An id is remembered as long as the server retains its job; forgotten entries are
// swept as the table grows, so its size follows the retained jobs. Thread-safe; callbacks run
// without locks.
#ifndef ISPQ_SERVER_ADMISSION_REQUEST_IDS_H_
#define ISPQ_SERVER_ADMISSION_REQUEST_IDS_H_

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/functional/any_invocable.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/synchronization/mutex.h"
#include "server/model/job.h"

namespace ispq::server {

// INVALID_ARGUMENT unless `request_id` is 1-64 characters of [A-Za-z0-9_-].
absl::Status ValidateRequestId(const std::string& request_id);

class RequestIds {
 public:
  using Outcome = absl::StatusOr<std::shared_ptr<Job>>;
  using Waiter = absl::AnyInvocable<void(Outcome) &&>;

  // `find_job` looks a job up by id among those the server retains (JobScheduler::Find).
  using JobFinder = std::function<std::shared_ptr<Job>(const std::string& id)>;
  explicit RequestIds(JobFinder find_job);

  // The claim of the first call with an id: admit the request, then pass the outcome to Complete.
  struct Ticket {
    std::string key;
  };
  // What a call with an id does: admit the request and Complete its `ticket`; or answer with
  // `outcome` (the existing job, or ALREADY_EXISTS); or neither: `waiter` gets the first call's
  // outcome from its Complete.
  struct Decision {
    std::optional<Ticket> ticket;
    std::optional<Outcome> outcome;
  };
  Decision Begin(const std::string& principal, const std::string& request_id,
                 std::string fingerprint, Waiter waiter);
  void Complete(const Ticket& ticket, const Outcome& outcome);

 private:
  struct Entry {
    std::string fingerprint;
    std::optional<std::string> job_id;  // unset while the first call is being admitted
    std::vector<Waiter> waiters;
  };
  // Drops the entries whose jobs the scheduler no longer retains, once the table has doubled.
  void SweepLocked() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  const JobFinder find_job_;
  absl::Mutex mutex_;
  absl::flat_hash_map<std::string, Entry> entries_ ABSL_GUARDED_BY(mutex_);
  size_t sweep_at_ ABSL_GUARDED_BY(mutex_) = 1024;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_REQUEST_IDS_H_
