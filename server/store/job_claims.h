// SPDX-License-Identifier: Apache-2.0
// Jobs queued in a shared store (server/store/postgres/postgres_job_store.h), claimed by the
// workers of any replica (server/jobs/job_claimer.h) under a lease that the claiming replica
// renews. A job whose lease expires (its replica died or stalled) is claimable again and is run
// from the start by whoever claims it: quantization is deterministic, so the result is the same.
// Each claim has an attempt number, and everything done under a claim (recording, giving back,
// failing) is fenced by it: a replica whose claim was superseded changes nothing.
#ifndef ISPQ_SERVER_STORE_JOB_CLAIMS_H_
#define ISPQ_SERVER_STORE_JOB_CLAIMS_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "absl/status/status.h"
#include "absl/time/time.h"
#include "ispq/v1/service.pb.h"
#include "server/model/job.h"

namespace ispq::server {

class JobClaims {
 public:
  virtual ~JobClaims() = default;

  struct Claim {
    std::string id;
    v1::QuantizeRequest request;  // as admitted by the replica that accepted the job
    int64_t request_bytes = 0;
    std::string owner;
    absl::Time create_time;
    int64_t next_sequence = 0;  // the number of the run's first event
    bool cancel_requested = false;
    int attempt = 1;  // 2 or more: an earlier run was lost with its replica
  };
  // The oldest job that is queued, or running under an expired lease, now leased to this
  // replica; nullopt if there is none or the store cannot be reached.
  virtual std::optional<Claim> ClaimNext() = 0;
  // `runner` runs `claim` here: its events are recorded under the claim from now on, its lease
  // renewed until its end is recorded.
  virtual void Adopt(std::shared_ptr<Job> runner, const Claim& claim) = 0;
  // Gives a claim back for another replica (this one cannot take it now).
  virtual void Release(const Claim& claim) = 0;
  // Ends a claimed job that can never run (its request no longer admits) with `status`.
  virtual void Fail(const Claim& claim, const absl::Status& status) = 0;
  // Jobs waiting in the store for any replica; -1 if unknown.
  virtual int QueuedCount() = 0;
  // `wake` is called, on some thread of the store, whenever a job may have become claimable.
  virtual void OnClaimable(std::function<void()> wake) = 0;
  // From now on a job interrupted here (shutdown) is given back for another replica to run
  // instead of ending with its partial result.
  virtual void BeginDraining() = 0;
  // How often to look for claimable jobs without a wake-up (expired leases send none).
  virtual absl::Duration poll_interval() const = 0;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_STORE_JOB_CLAIMS_H_
