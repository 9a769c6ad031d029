// SPDX-License-Identifier: Apache-2.0
#include "tests/server/http/http_test_service.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/synchronization/notification.h"
#include "absl/time/clock.h"
#include "server/admission/request_bytes.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/test_data.h"

namespace ispq::server::http {

HttpTestService::HttpTestService(int workers, int64_t budget_bytes)
    : budget(budget_bytes),
      meshes(10),
      scheduler({.workers = workers, .max_queued_jobs = 8, .retention = {}}, metrics, &budget),
      memory(budget, scheduler, meshes, metrics),
      service({scheduler, meshes, metrics, memory}, JobLimits{.max_arcs = 1000000},
              AdmissionConfig{}),
      authenticator(AuthenticationConfig{.tokens = {{.principal = "alice", .token = kAliceToken},
                                                    {.principal = "bob", .token = kBobToken},
                                                    {.principal = "admin", .token = kAdminToken}},
                                         .client_certificates = false,
                                         .admin_principals = {"admin"}}) {}

HttpParts HttpTestService::parts() {
  return HttpParts{.service = service,
                   .authenticator = authenticator,
                   .memory = memory,
                   .metrics = metrics,
                   .live = [this] { return live.load(); },
                   .ready = [this] { return ready.load(); }};
}

std::shared_ptr<Job> HttpTestService::SubmitOrDie(const v1::QuantizeRequest& request,
                                                  const std::string& owner) {
  const std::string bytes = request.SerializeAsString();
  JobSubmission submission;
  submission.principal = Principal{.name = owner};
  submission.raw.bytes = std::make_unique<StringRequestBytes>(bytes);
  submission.raw.size = static_cast<int64_t>(bytes.size());
  submission.peer = "test";
  absl::Notification answered;
  JobSubmission::Outcome outcome = absl::UnknownError("never answered");
  submission.answer = [&](const JobSubmission::Outcome& decided) {
    outcome = decided;
    answered.Notify();
  };
  service.Submit(std::move(submission));
  EXPECT_TRUE(answered.WaitForNotificationWithTimeout(testing::kSafetyNet));
  EXPECT_TRUE(outcome.ok()) << outcome.status();
  return outcome.ok() ? *outcome : nullptr;
}

v1::QuantizeRequest NotchRequest(const std::string& request_id) {
  v1::QuantizeRequest request;
  *request.mutable_mesh() =
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  request.mutable_options()->mutable_scaling()->set_level_percent(25);
  request.set_request_id(request_id);
  return request;
}

std::string ClientJson(const google::protobuf::Message& message) {
  std::string json;
  const auto printed = google::protobuf::util::MessageToJsonString(message, &json);
  EXPECT_TRUE(printed.ok()) << printed.message();
  return json;
}

void RecordingResponder::Answer(HttpResponse response) {
  absl::MutexLock lock(&mutex_);
  ++answers_;
  if (!answer_.has_value()) answer_ = std::move(response);
}

bool RecordingResponder::Answered() const {
  absl::MutexLock lock(&mutex_);
  return answers_ > 0;
}

HttpResponse RecordingResponder::WaitForAnswer() {
  absl::MutexLock lock(&mutex_);
  auto answered = [this]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return answer_.has_value(); };
  if (!mutex_.AwaitWithTimeout(absl::Condition(&answered), testing::kSafetyNet)) {
    ADD_FAILURE() << "the route never answered";
    HttpResponse none;
    none.status = 0;
    return none;
  }
  return *std::move(answer_);
}

int RecordingResponder::answers() const {
  absl::MutexLock lock(&mutex_);
  return answers_;
}

HttpRequest RouteRequest(const std::string& method, const std::string& path, const std::string& id,
                         const std::string& principal) {
  HttpRequest request;
  request.method = method;
  request.path = path;
  request.id = id;
  request.peer = "127.0.0.1:40000";
  request.principal = Principal{.name = principal, .admin = principal == "admin"};
  return request;
}

std::string RawHttpExchange(int port, const std::string& bytes, bool ipv6, int* local_port) {
  const absl::Time deadline = absl::Now() + testing::kSafetyNet;
  sockaddr_storage address = {};
  socklen_t length = 0;
  if (ipv6) {
    auto* v6 = reinterpret_cast<sockaddr_in6*>(&address);
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(static_cast<uint16_t>(port));
    v6->sin6_addr = in6addr_loopback;
    length = sizeof(sockaddr_in6);
  } else {
    auto* v4 = reinterpret_cast<sockaddr_in*>(&address);
    v4->sin_family = AF_INET;
    v4->sin_port = htons(static_cast<uint16_t>(port));
    v4->sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    length = sizeof(sockaddr_in);
  }
  const int fd = socket(address.ss_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return "";
  std::string answer;
  if (connect(fd, reinterpret_cast<sockaddr*>(&address), length) == 0) {
    if (local_port != nullptr) {
      sockaddr_storage local = {};
      socklen_t local_length = sizeof(local);
      getsockname(fd, reinterpret_cast<sockaddr*>(&local), &local_length);
      // sin_port and sin6_port sit at the same offset.
      *local_port = ntohs(reinterpret_cast<const sockaddr_in*>(&local)->sin_port);
    }
    // A refusal may come before the server has taken everything: read it anyway.
    for (size_t sent = 0; sent < bytes.size();) {
      const ssize_t wrote = send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
      if (wrote <= 0) break;
      sent += static_cast<size_t>(wrote);
    }
    while (true) {
      const int64_t left = absl::ToInt64Milliseconds(deadline - absl::Now());
      pollfd watched = {.fd = fd, .events = POLLIN, .revents = 0};
      if (left <= 0 || poll(&watched, 1, static_cast<int>(left)) != 1) break;
      char chunk[16384];
      const ssize_t got = recv(fd, chunk, sizeof(chunk), 0);
      if (got <= 0) break;
      answer.append(chunk, static_cast<size_t>(got));
    }
  }
  close(fd);
  return answer;
}

int RawStatus(const std::string& answer) {
  int status = 0;
  if (answer.size() < 12 || answer.compare(0, 5, "HTTP/") != 0 ||
      !absl::SimpleAtoi(answer.substr(9, 3), &status)) {
    return 0;
  }
  return status;
}

}  // namespace ispq::server::http
