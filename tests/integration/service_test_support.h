// SPDX-License-Identifier: Apache-2.0
// What the service's integration tests (and the load test) share: starting the real server,
// connecting the real client, building requests from real T-meshes, waiting for job states,
// the long-running job, and checking every result with the product's validator.
#ifndef ISPQ_TESTS_INTEGRATION_SERVICE_TEST_SUPPORT_H_
#define ISPQ_TESTS_INTEGRATION_SERVICE_TEST_SUPPORT_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "client/quantizer_client.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"
#include "ispq/v1/tmesh.pb.h"
#include "tests/integration/server_process.h"

namespace ispq::testing {

// Generous: the tests share 2 cores with the rest of the suite.
inline constexpr absl::Duration kJobTimeout = absl::Seconds(300);

// Stream options with a deadline and an optional event handler.
client::StreamOptions StreamFor(absl::Duration timeout, client::EventHandler on_event = nullptr);

// Starts ispq-server with `flags`; fails the test (returns nullptr) if it does not come up.
std::unique_ptr<ServerProcess> StartServerOrFail(const std::vector<std::string>& flags);

client::QuantizerClient ClientOf(const ServerProcess& server, const std::string& auth_token = "");

// A request for `mesh` at a resolution level.
v1::QuantizeRequest RequestFor(const v1::TMesh& mesh, int level_percent);
v1::QuantizeRequest StoredMeshRequest(const std::string& stored_mesh, int level_percent);

// hex-me/s07c_notch of the real set, and a real T-mesh by model name.
const v1::TMesh& NotchMesh();
v1::TMesh RealMeshNamed(const std::string& model);

// A real T-mesh (disjoint copies of one of the real set, see tmesh_copies.h) whose level-100 solve
// takes about `seconds` in-process on this machine; one copy is timed once per test binary.
v1::TMesh MeshTakingSeconds(double seconds);
// About a minute: long enough to still run whenever a test acts on it; tests cancel it.
const v1::TMesh& LongRunningMesh();
// `copies` disjoint copies of the T-mesh the long-running jobs are made of (a femur shell: 296
// arcs, about 60 KB each), for requests whose size does not depend on the machine's speed.
v1::TMesh FemurCopies(int copies);
// 400 of them: about 24 MB and 120k arcs, a request near the default message limit.
const v1::TMesh& LargeMesh();

// Whether `result` is valid for `mesh` according to the validator (core/quantization_validator.h)
// and says so itself; the failure message lists the violations.
::testing::AssertionResult IsValidResult(const v1::TMesh& mesh,
                                         const v1::QuantizationResult& result);

// Polls GetJob until the job has ended, or fails at `timeout`.
absl::StatusOr<v1::Job> WaitUntilDone(client::QuantizerClient& client, const std::string& job,
                                      absl::Duration timeout = kJobTimeout);
// Polls GetJob until the job is in `state` (or has ended, which is then an error).
absl::Status WaitForState(client::QuantizerClient& client, const std::string& job,
                          v1::JobState state, absl::Duration timeout = kJobTimeout);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_INTEGRATION_SERVICE_TEST_SUPPORT_H_
