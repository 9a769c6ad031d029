// SPDX-License-Identifier: Apache-2.0
// The JSON API over jobs, each route called as the dispatcher calls it (the caller already
// authenticated, the body received): every route is the job service's operation with its
// semantics and errors, its query parameters reach the service, a submission's JSON body is
// checked and converted before it is admitted, and every route authenticates and runs off the
// event thread. Over a live server: http_server_test.cc and tests/integration/http_api_test.cc.
#include "server/http/job_routes.h"

#include <memory>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "core/proto/quantization_proto.h"
#include "core/quantization_validator.h"
#include "gmock/gmock.h"
#include "google/protobuf/struct.pb.h"
#include "gtest/gtest.h"
#include "server/http/http_router.h"
#include "tests/server/http/http_test_service.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/test_data.h"

namespace ispq::server::http {
namespace {

using ::testing::HasSubstr;

std::string ErrorMessage(const HttpResponse& response) {
  return ParseJson<google::protobuf::Struct>(response.body).fields().at("message").string_value();
}

// The job routes over one service.
class JobRoutes {
 public:
  explicit JobRoutes(HttpTestService& service, HttpLimits limits = {})
      : limits_(std::move(limits)), parts_(service.parts()) {
    AddJobRoutes(router_, parts_, limits_);
  }

  const Route* Find(const std::string& method, const std::string& path, std::string* id) const {
    return router_.Match(method, path, id);
  }

  // Runs the route for `method` `path` as `principal` with `query` and `body`; its answer.
  HttpResponse Call(const std::string& method, const std::string& path,
                    const std::string& principal = "alice", HttpFields query = {},
                    std::string body = "") {
    std::string id;
    const Route* route = router_.Match(method, path, &id);
    EXPECT_NE(route, nullptr) << method << " " << path;
    if (route == nullptr) return HttpResponse();
    HttpRequest request = RouteRequest(method, path, id, principal);
    request.query = std::move(query);
    request.body = std::move(body);
    auto responder = std::make_shared<RecordingResponder>();
    route->handle(request, responder);
    HttpResponse answer = responder->WaitForAnswer();
    EXPECT_EQ(responder->answers(), 1) << "a route answers exactly once";
    if (route->takes_body) {
      EXPECT_TRUE(request.body.empty()) << "the JSON body is let go once converted";
    }
    return answer;
  }

  v1::Job Submit(const v1::QuantizeRequest& request, const std::string& principal = "alice") {
    const HttpResponse answer = Call("POST", "/v1/jobs", principal, {}, ClientJson(request));
    EXPECT_EQ(answer.status, 200) << answer.body;
    return ParseJson<v1::Job>(answer.body);
  }

 private:
  const HttpLimits limits_;
  const HttpParts parts_;
  Router router_;
};

class JobRoutesTest : public ::testing::Test {
 protected:
  HttpTestService service_;
  JobRoutes routes_{service_};
};

TEST_F(JobRoutesTest, EveryRouteAuthenticatesAndRunsOffTheEventThread) {
  std::string id;
  const Route* submit = routes_.Find("POST", "/v1/jobs", &id);
  ASSERT_NE(submit, nullptr);
  EXPECT_TRUE(submit->authenticated);
  EXPECT_TRUE(submit->takes_body);
  EXPECT_EQ(submit->lane, Lane::kParse);
  EXPECT_FALSE(submit->any_host);
  // A submission that times out may have been admitted: the client is told how to find out.
  EXPECT_THAT(submit->timeout_message, HasSubstr("requestId"));

  for (const auto& [method, path] : std::vector<std::pair<std::string, std::string>>{
           {"GET", "/v1/jobs"}, {"GET", "/v1/jobs/abc"}, {"POST", "/v1/jobs/abc:cancel"}}) {
    const Route* route = routes_.Find(method, path, &id);
    ASSERT_NE(route, nullptr) << method << " " << path;
    EXPECT_TRUE(route->authenticated) << path;
    EXPECT_FALSE(route->takes_body) << path;
    EXPECT_FALSE(route->any_host) << path;
    EXPECT_EQ(route->lane, Lane::kLookup) << path;
  }
  // The watch route is the event stream route's, not one of these.
  EXPECT_EQ(routes_.Find("GET", "/v1/jobs/abc:watch", &id), nullptr);
}

TEST_F(JobRoutesTest, ASubmissionIsAdmittedAsTheCallersJob) {
  const v1::Job job = routes_.Submit(NotchRequest("batch-1"));
  EXPECT_TRUE(absl::StartsWith(job.name(), "jobs/")) << job.name();
  EXPECT_EQ(job.owner(), "alice");
  EXPECT_EQ(job.state(), v1::QUEUED);
  EXPECT_EQ(job.request_id(), "batch-1");
  EXPECT_GT(job.mesh_stats().arcs(), 0);

  v1::GetJobRequest get;
  get.set_name(job.name());
  const absl::StatusOr<v1::Job> stored = service_.service.GetJob(get, Principal{.name = "alice"});
  ASSERT_TRUE(stored.ok()) << stored.status();
  EXPECT_EQ(stored->request_id(), "batch-1");

  // The same request id is the same job, over HTTP as over gRPC.
  EXPECT_EQ(routes_.Submit(NotchRequest("batch-1")).name(), job.name());
  EXPECT_NE(routes_.Submit(NotchRequest("batch-1"), "bob").name(), job.name());
  // Nothing of the bodies stays in the budget once the answers are let go.
  EXPECT_EQ(service_.budget.used(MemoryUse::kRequests), 0);
}

TEST_F(JobRoutesTest, ABadBodyIsRefusedAsInvalidBeforeAdmission) {
  v1::QuantizeRequest bad_arc = NotchRequest();
  bad_arc.mutable_mesh()->mutable_arcs(3)->set_length(-1);
  const std::vector<std::pair<std::string, std::string>> bodies = {
      {"", "empty"},  {"{\"mesh\": ", "in JSON"},     {"{\"noSuchField\": 1}", "noSuchField"},
      {"[1, 2]", ""}, {ClientJson(bad_arc), "arc 3"},
  };
  for (const auto& [body, named] : bodies) {
    const HttpResponse answer = routes_.Call("POST", "/v1/jobs", "alice", {}, body);
    EXPECT_EQ(answer.status, 400) << body.substr(0, 80);
    EXPECT_THAT(ErrorMessage(answer), HasSubstr(named)) << body.substr(0, 80);
  }
  v1::ServerStats stats;
  service_.metrics.FillProto(stats);
  EXPECT_EQ(stats.rejected_invalid_total(), static_cast<int64_t>(bodies.size()));
  EXPECT_EQ(service_.service.Stats().queued_jobs(), 0);
  EXPECT_EQ(service_.budget.used(MemoryUse::kRequests), 0);
}

TEST_F(JobRoutesTest, ABinaryBodyIsTheRequestGrpcTakes) {
  std::string id;
  const Route* submit = routes_.Find("POST", "/v1/jobs", &id);
  ASSERT_NE(submit, nullptr);
  EXPECT_TRUE(submit->takes_protobuf);
  auto post = [&](std::string body) {
    HttpRequest request = RouteRequest("POST", "/v1/jobs");
    request.headers.emplace_back("content-type", "application/x-protobuf");
    request.body = std::move(body);
    auto responder = std::make_shared<RecordingResponder>();
    submit->handle(request, responder);
    EXPECT_TRUE(request.body.empty()) << "the body is let go once handed on";
    return responder->WaitForAnswer();
  };
  const HttpResponse admitted = post(NotchRequest("binary-1").SerializeAsString());
  ASSERT_EQ(admitted.status, 200) << admitted.body;
  const v1::Job job = ParseJson<v1::Job>(admitted.body);
  EXPECT_EQ(job.request_id(), "binary-1");
  EXPECT_EQ(job.mesh_stats().arcs(), NotchRequest().mesh().arcs_size());
  // The same request in JSON is the same job: one request, two encodings.
  EXPECT_EQ(routes_.Submit(NotchRequest("binary-1")).name(), job.name());

  v1::QuantizeRequest bad_arc = NotchRequest();
  bad_arc.mutable_mesh()->mutable_arcs(3)->set_length(-1);
  for (const auto& [body, named] : std::vector<std::pair<std::string, std::string>>{
           {bad_arc.SerializeAsString(), "arc 3"}, {"\xff\xff\xff", ""}, {"", "empty"}}) {
    const HttpResponse refused = post(body);
    EXPECT_EQ(refused.status, 400) << named;
    EXPECT_THAT(ErrorMessage(refused), HasSubstr(named));
  }
  EXPECT_EQ(service_.budget.used(MemoryUse::kRequests), 0);
}

TEST_F(JobRoutesTest, AJobIsVisibleToItsOwnerAndAdminsOnly) {
  const v1::Job job = routes_.Submit(NotchRequest());
  const std::string path = "/v1/" + job.name();
  const HttpResponse owners = routes_.Call("GET", path, "alice");
  EXPECT_EQ(owners.status, 200);
  EXPECT_EQ(ParseJson<v1::Job>(owners.body).name(), job.name());
  EXPECT_EQ(routes_.Call("GET", path, "admin").status, 200);
  EXPECT_EQ(routes_.Call("GET", path, "bob").status, 404);
  EXPECT_EQ(routes_.Call("GET", "/v1/jobs/0000000000000000", "alice").status, 404);
  EXPECT_EQ(routes_.Call("POST", path + ":cancel", "bob").status, 404);
  EXPECT_EQ(routes_.Call("GET", path, "alice").status, 200) << "bob's cancel changed nothing";

  const HttpResponse cancelled = routes_.Call("POST", path + ":cancel", "alice");
  ASSERT_EQ(cancelled.status, 200) << cancelled.body;
  const v1::Job after = ParseJson<v1::Job>(cancelled.body);
  EXPECT_EQ(after.state(), v1::CANCELLED);
  EXPECT_TRUE(after.done());
}

TEST_F(JobRoutesTest, AListIsTheCallersJobsNewestFirstFilteredAndPaged) {
  std::vector<std::string> names;
  for (int i = 0; i < 3; ++i) names.push_back(routes_.Submit(NotchRequest()).name());
  routes_.Submit(NotchRequest(), "bob");
  ASSERT_EQ(routes_.Call("POST", "/v1/" + names[1] + ":cancel").status, 200);

  const HttpResponse all = routes_.Call("GET", "/v1/jobs");
  ASSERT_EQ(all.status, 200) << all.body;
  const auto listed = ParseJson<v1::ListJobsResponse>(all.body);
  ASSERT_EQ(listed.jobs_size(), 3);
  EXPECT_EQ(listed.jobs(0).name(), names[2]);
  EXPECT_EQ(listed.jobs(2).name(), names[0]);

  const auto cancelled = ParseJson<v1::ListJobsResponse>(
      routes_.Call("GET", "/v1/jobs", "alice", {{"state", "CANCELLED"}}).body);
  ASSERT_EQ(cancelled.jobs_size(), 1);
  EXPECT_EQ(cancelled.jobs(0).name(), names[1]);

  const auto first = ParseJson<v1::ListJobsResponse>(
      routes_.Call("GET", "/v1/jobs", "alice", {{"pageSize", "2"}}).body);
  ASSERT_EQ(first.jobs_size(), 2);
  ASSERT_FALSE(first.next_page_token().empty());
  const auto second = ParseJson<v1::ListJobsResponse>(
      routes_
          .Call("GET", "/v1/jobs", "alice",
                {{"pageSize", "2"}, {"pageToken", first.next_page_token()}})
          .body);
  ASSERT_EQ(second.jobs_size(), 1);
  EXPECT_EQ(second.jobs(0).name(), names[0]);
  EXPECT_TRUE(second.next_page_token().empty());

  EXPECT_EQ(
      ParseJson<v1::ListJobsResponse>(routes_.Call("GET", "/v1/jobs", "admin").body).jobs_size(),
      4);
}

TEST_F(JobRoutesTest, AMalformedParameterIsRefusedNamingIt) {
  const std::vector<std::pair<std::string, HttpFields>> refused = {
      {"pageSize", {{"pageSize", "-1"}}},         {"pageSize", {{"pageSize", "ten"}}},
      {"pageSize", {{"pageSize", "4294967296"}}}, {"state", {{"state", "SLEEPING"}}},
      {"view", {{"view", "EVERYTHING"}}},
  };
  for (const auto& [name, query] : refused) {
    const HttpResponse answer = routes_.Call("GET", "/v1/jobs", "alice", query);
    EXPECT_EQ(answer.status, 400) << query.front().second;
    EXPECT_THAT(ErrorMessage(answer), HasSubstr(name));
  }
  const HttpResponse get = routes_.Call("GET", "/v1/jobs/abc", "alice", {{"view", "ALL"}});
  EXPECT_EQ(get.status, 400);
  EXPECT_THAT(ErrorMessage(get), HasSubstr("view"));
}

// The view parameter reaches the service: FULL (GetJob's default) has the result's q, BASIC not.
TEST_F(JobRoutesTest, TheViewParameterChoosesWhatOfTheResultIsSent) {
  HttpTestService service(/*workers=*/1);  // this one runs its jobs
  JobRoutes routes(service);
  const v1::Job job = routes.Submit(NotchRequest());
  const std::string path = "/v1/" + job.name();
  ASSERT_TRUE(testing::WaitUntil(
      [&] { return ParseJson<v1::Job>(routes.Call("GET", path, "alice").body).done(); }));

  const v1::Job full = ParseJson<v1::Job>(routes.Call("GET", path, "alice").body);
  ASSERT_EQ(full.state(), v1::SUCCEEDED);
  ASSERT_GT(full.result().q_size(), 0);
  const TMesh mesh =
      testing::LoadTMeshOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  const absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(full.result(), mesh);
  ASSERT_TRUE(q.ok()) << q.status();
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, *q);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_TRUE(report->valid()) << report->Describe();

  const v1::Job basic =
      ParseJson<v1::Job>(routes.Call("GET", path, "alice", {{"view", "BASIC"}}).body);
  EXPECT_EQ(basic.state(), v1::SUCCEEDED);
  EXPECT_EQ(basic.result().q_size(), 0);
  EXPECT_EQ(ParseJson<v1::Job>(routes.Call("GET", path, "alice", {{"view", "FULL"}}).body)
                .result()
                .q_size(),
            full.result().q_size());
  // A list is BASIC unless asked otherwise.
  EXPECT_EQ(ParseJson<v1::ListJobsResponse>(routes.Call("GET", "/v1/jobs").body)
                .jobs(0)
                .result()
                .q_size(),
            0);
  EXPECT_EQ(ParseJson<v1::ListJobsResponse>(
                routes.Call("GET", "/v1/jobs", "alice", {{"view", "FULL"}}).body)
                .jobs(0)
                .result()
                .q_size(),
            full.result().q_size());
}

}  // namespace
}  // namespace ispq::server::http
