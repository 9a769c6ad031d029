// SPDX-License-Identifier: Apache-2.0
// Jobs for the unit tests of the server's parts: a real (bundled) T-mesh behind a minimal spec.
#ifndef ISPQ_TESTS_SERVER_SERVER_TEST_JOBS_H_
#define ISPQ_TESTS_SERVER_SERVER_TEST_JOBS_H_

#include <memory>
#include <string>

#include "absl/time/time.h"
#include "server/model/job.h"

namespace ispq::server {

JobSpec NotchJobSpec();
std::shared_ptr<Job> NewNotchJob(const std::string& id, absl::Time now = absl::Now());

}  // namespace ispq::server

#endif  // ISPQ_TESTS_SERVER_SERVER_TEST_JOBS_H_
