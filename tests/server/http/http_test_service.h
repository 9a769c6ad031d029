// SPDX-License-Identifier: Apache-2.0
// What the unit tests of the HTTP side's routes and server (server/http/) share: the job service
// on the in-memory stores, as tests/server/service/job_service_test.cc builds it, with bearer
// tokens for alice, bob and an admin, and the HttpParts the routes take; a Responder that keeps
// the answer a route gives; and a raw exchange of bytes with a server on loopback, for requests
// the JSON client (tests/integration/http_client.h) does not send.
#ifndef ISPQ_TESTS_SERVER_HTTP_HTTP_TEST_SERVICE_H_
#define ISPQ_TESTS_SERVER_HTTP_HTTP_TEST_SERVICE_H_

#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"
#include "server/admission/memory_admission.h"
#include "server/auth/authenticator.h"
#include "server/http/http_message.h"
#include "server/http/http_parts.h"
#include "server/jobs/job_scheduler.h"
#include "server/memory/memory_budget.h"
#include "server/metrics/server_metrics.h"
#include "server/service/job_service.h"
#include "server/store/mesh_store.h"

namespace ispq::server::http {

inline constexpr char kAliceToken[] = "alice-token";
inline constexpr char kBobToken[] = "bob-token";
inline constexpr char kAdminToken[] = "admin-token";

// The job service and what the HTTP side works with. Without workers (the default) a submitted
// job stays queued until it is cancelled, so that the tests decide when a job ends.
class HttpTestService {
 public:
  explicit HttpTestService(int workers = 0, int64_t budget_bytes = int64_t{1} << 30);

  HttpParts parts();
  // Submits `request` as `owner` through the service and waits for the admitted job.
  std::shared_ptr<Job> SubmitOrDie(const v1::QuantizeRequest& request, const std::string& owner);

  // What /healthz and /readyz report.
  std::atomic<bool> live{true};
  std::atomic<bool> ready{true};

  ServerMetrics metrics;
  MemoryBudget budget;
  InMemoryMeshStore meshes;
  JobScheduler scheduler;
  MemoryAdmission memory;
  JobService service;
  Authenticator authenticator;
};

// The notch T-mesh's request (a small mesh from tests/data), as the service tests submit it.
v1::QuantizeRequest NotchRequest(const std::string& request_id = "");
// `message` in protobuf JSON as a client writes it (protobuf's printer, not the server's).
std::string ClientJson(const google::protobuf::Message& message);
// Keeps what a route answers; thread-safe.
class RecordingResponder : public Responder {
 public:
  void Answer(HttpResponse response) override;
  bool Answered() const override;
  // Waits (bounded by the safety net) for the answer; fails the test without one.
  HttpResponse WaitForAnswer();
  int answers() const;

 private:
  mutable absl::Mutex mutex_;
  int answers_ ABSL_GUARDED_BY(mutex_) = 0;
  std::optional<HttpResponse> answer_ ABSL_GUARDED_BY(mutex_);
};

// An HttpRequest as the dispatcher hands it to a route.
HttpRequest RouteRequest(const std::string& method, const std::string& path,
                         const std::string& id = "", const std::string& principal = "alice");

// Sends `bytes` to 127.0.0.1:`port` ([::1] with `ipv6`) and returns everything the server sends
// until it closes the connection (or the safety net passes); `local_port` (if set) is the
// client's own port.
std::string RawHttpExchange(int port, const std::string& bytes, bool ipv6 = false,
                            int* local_port = nullptr);
// The status code of a raw answer ("HTTP/1.1 404 ..."), 0 if there is none.
int RawStatus(const std::string& answer);

// `json` parsed into a `Message`; fails the test if it does not parse.
template <typename Message>
Message ParseJson(const std::string& json) {
  Message message;
  const auto parsed = google::protobuf::util::JsonStringToMessage(json, &message);
  EXPECT_TRUE(parsed.ok()) << parsed.message() << " in " << json.substr(0, 500);
  return message;
}

}  // namespace ispq::server::http

#endif  // ISPQ_TESTS_SERVER_HTTP_HTTP_TEST_SERVICE_H_
