// SPDX-License-Identifier: Apache-2.0
// The HTTP side's JSON API (--http_listen, server/http/job_routes.h) against a live server: the
// same jobs, answers, errors, principals and request ids as the gRPC methods, with gRPC codes
// mapped to HTTP statuses and google.rpc.Status-like error bodies. Results are checked by the
// validator.
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "absl/time/clock.h"
#include "gmock/gmock.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "tests/integration/http_test_support.h"
#include "tests/integration/service_test_support.h"

namespace ispq::testing {
namespace {

using ::google::protobuf::util::MessageDifferencer;
using ::testing::HasSubstr;

// The error body's fields.
struct ErrorBody {
  double code = -1;
  std::string status;
  std::string message;
};
ErrorBody ErrorOf(const HttpAnswer& answer) {
  const google::protobuf::Struct body = FromJson<google::protobuf::Struct>(answer.body);
  ErrorBody error;
  const auto& fields = body.fields();
  if (fields.contains("code")) error.code = fields.at("code").number_value();
  if (fields.contains("status")) error.status = fields.at("status").string_value();
  if (fields.contains("message")) error.message = fields.at("message").string_value();
  return error;
}

std::string JobPath(const std::string& name, const std::string& suffix = "") {
  return absl::StrCat("/v1/", name, suffix);
}

TEST(HttpApiTest, SubmittedJobIsTheSameJobOverGrpcAndHttp) {
  HttpServer server = StartHttpServerOrFail({"--workers=2"});
  ASSERT_NE(server.process, nullptr);
  client::QuantizerClient grpc_client = ClientOf(*server.process);
  const v1::TMesh& mesh = NotchMesh();

  const HttpAnswer submitted =
      HttpPost(server.http_port, "/v1/jobs", RequestJson(RequestFor(mesh, 25)));
  ASSERT_EQ(submitted.status, 200) << submitted.body;
  EXPECT_THAT(submitted.content_type, HasSubstr("application/json"));
  const v1::Job job = FromJson<v1::Job>(submitted.body);
  EXPECT_THAT(job.name(), ::testing::StartsWith("jobs/"));
  EXPECT_EQ(job.mesh_stats().arcs(), mesh.arcs_size());
  EXPECT_EQ(job.options().scaling().level_percent(), 25);

  const absl::StatusOr<v1::Job> done = WaitUntilDone(grpc_client, job.name());
  ASSERT_TRUE(done.ok()) << done.status();
  ASSERT_EQ(done->state(), v1::SUCCEEDED);
  EXPECT_TRUE(IsValidResult(mesh, done->result()));

  // GET answers what GetJob answers, field for field.
  const HttpAnswer got = HttpGet(server.http_port, JobPath(job.name()));
  ASSERT_EQ(got.status, 200) << got.body;
  const v1::Job over_http = FromJson<v1::Job>(got.body);
  EXPECT_TRUE(MessageDifferencer::Equals(over_http, *done)) << over_http.DebugString() << "\nvs\n"
                                                            << done->DebugString();
  EXPECT_TRUE(IsValidResult(mesh, over_http.result()));

  const HttpAnswer basic = HttpGet(server.http_port, JobPath(job.name(), "?view=BASIC"));
  ASSERT_EQ(basic.status, 200) << basic.body;
  EXPECT_EQ(FromJson<v1::Job>(basic.body).result().q_size(), 0);

  // The list is ListJobs' (basic view, newest first).
  const HttpAnswer listed = HttpGet(server.http_port, "/v1/jobs");
  ASSERT_EQ(listed.status, 200) << listed.body;
  const absl::StatusOr<v1::ListJobsResponse> grpc_list = grpc_client.ListJobs({});
  ASSERT_TRUE(grpc_list.ok());
  EXPECT_TRUE(MessageDifferencer::Equals(FromJson<v1::ListJobsResponse>(listed.body), *grpc_list));
  const HttpAnswer running = HttpGet(server.http_port, "/v1/jobs?state=RUNNING&pageSize=5");
  ASSERT_EQ(running.status, 200) << running.body;
  EXPECT_EQ(FromJson<v1::ListJobsResponse>(running.body).jobs_size(), 0);
}

TEST(HttpApiTest, ErrorsAreTheGrpcErrorsWithMappedHttpStatuses) {
  HttpServer server = StartHttpServerOrFail({"--workers=1", "--max_message_bytes=400000"});
  ASSERT_NE(server.process, nullptr);
  const int port = server.http_port;

  // An invalid T-mesh: the validator's message, naming the element.
  v1::QuantizeRequest invalid = RequestFor(NotchMesh(), 25);
  invalid.mutable_mesh()->mutable_arcs(3)->set_length(-1);
  HttpAnswer answer = HttpPost(port, "/v1/jobs", RequestJson(invalid));
  EXPECT_EQ(answer.status, 400);
  ErrorBody error = ErrorOf(answer);
  EXPECT_EQ(error.code, 3);
  EXPECT_EQ(error.status, "INVALID_ARGUMENT");
  EXPECT_THAT(error.message, HasSubstr("arc 3"));

  // Bodies that are no QuantizeRequest in JSON.
  answer = HttpPost(port, "/v1/jobs", "{\"mesh\": [1, 2");
  EXPECT_EQ(answer.status, 400);
  EXPECT_THAT(ErrorOf(answer).message, HasSubstr("ispq.v1.QuantizeRequest"));
  answer = HttpPost(port, "/v1/jobs", "{\"meshh\": {}}");
  EXPECT_EQ(answer.status, 400);
  EXPECT_THAT(ErrorOf(answer).message, HasSubstr("meshh"));
  answer = HttpPost(port, "/v1/jobs", "");
  EXPECT_EQ(answer.status, 400);
  EXPECT_THAT(ErrorOf(answer).message, HasSubstr("empty"));
  // A string field past the server's limit, as over gRPC.
  v1::QuantizeRequest long_name = RequestFor(NotchMesh(), 25);
  long_name.mutable_mesh()->set_name(std::string(5000, 'x'));
  answer = HttpPost(port, "/v1/jobs", RequestJson(long_name));
  EXPECT_EQ(answer.status, 400);
  EXPECT_THAT(ErrorOf(answer).message, HasSubstr("mesh.name"));

  // A body past --max_message_bytes is refused before it is read.
  answer = HttpPost(port, "/v1/jobs", RequestJson(RequestFor(FemurCopies(10), 25)));
  EXPECT_EQ(answer.status, 413);
  EXPECT_EQ(ErrorOf(answer).status, "RESOURCE_EXHAUSTED");

  // Unknown jobs, malformed names and parameters, unknown routes.
  answer = HttpGet(port, "/v1/jobs/0123456789abcdef");
  EXPECT_EQ(answer.status, 404);
  EXPECT_EQ(ErrorOf(answer).status, "NOT_FOUND");
  EXPECT_THAT(ErrorOf(answer).message, HasSubstr("jobs/0123456789abcdef"));
  EXPECT_EQ(HttpPost(port, "/v1/jobs/0123456789abcdef:cancel", "").status, 404);
  EXPECT_EQ(HttpGet(port, "/v1/jobs/0123456789abcdef:watch").status, 404);
  answer = HttpGet(port, "/v1/jobs?state=DONE");
  EXPECT_EQ(answer.status, 400);
  EXPECT_THAT(ErrorOf(answer).message, HasSubstr("state=DONE"));
  answer = HttpGet(port, "/v1/jobs?pageSize=-3");
  EXPECT_EQ(answer.status, 400);
  EXPECT_THAT(ErrorOf(answer).message, HasSubstr("pageSize"));
  answer = HttpGet(port, "/v1/jobs?pageToken=forged");
  EXPECT_EQ(answer.status, 400);
  EXPECT_EQ(ErrorOf(answer).status, "INVALID_ARGUMENT");
  answer = HttpGet(port, "/v1/nothing");
  EXPECT_EQ(answer.status, 404);
  EXPECT_THAT(ErrorOf(answer).message, HasSubstr("/v1/nothing"));

  // The server is fine afterwards.
  answer = HttpPost(port, "/v1/jobs", RequestJson(RequestFor(NotchMesh(), 10)));
  EXPECT_EQ(answer.status, 200) << answer.body;
}

TEST(HttpApiTest, CancelStopsARunningJob) {
  HttpServer server = StartHttpServerOrFail({"--workers=1"});
  ASSERT_NE(server.process, nullptr);
  client::QuantizerClient grpc_client = ClientOf(*server.process);
  // The long-running mesh is sized by the engine's speed (up to 24 MB); stored first, the body
  // names it instead of carrying it past the HTTP body limit.
  const absl::StatusOr<v1::Mesh> stored = grpc_client.CreateMesh(LongRunningMesh());
  ASSERT_TRUE(stored.ok()) << stored.status();
  const HttpAnswer submitted =
      HttpPost(server.http_port, "/v1/jobs", RequestJson(StoredMeshRequest(stored->name(), 100)));
  ASSERT_EQ(submitted.status, 200) << submitted.body;
  const std::string name = FromJson<v1::Job>(submitted.body).name();
  ASSERT_TRUE(WaitForState(grpc_client, name, v1::RUNNING).ok());

  const HttpAnswer cancelled = HttpPost(server.http_port, JobPath(name, ":cancel"), "");
  ASSERT_EQ(cancelled.status, 200) << cancelled.body;
  EXPECT_EQ(FromJson<v1::Job>(cancelled.body).name(), name);
  // CANCELLED, not SUCCEEDED, however long the cancel takes on a loaded machine.
  const absl::StatusOr<v1::Job> done = WaitUntilDone(grpc_client, name);
  ASSERT_TRUE(done.ok()) << done.status();
  EXPECT_EQ(done->state(), v1::CANCELLED);
  // An interrupted job returns its best valid quantization if it found one.
  if (done->result().valid()) {
    EXPECT_TRUE(IsValidResult(LongRunningMesh(), done->result()));
  }
}

TEST(HttpApiTest, TokensAndPrincipalsAreTheGrpcSides) {
  const std::string tokens_file = absl::StrCat(::testing::TempDir(), "/http_tokens");
  {
    FILE* out = fopen(tokens_file.c_str(), "w");
    ASSERT_NE(out, nullptr);
    fputs("alice alice-token-0123\nbob bob-token-4567\n", out);
    fclose(out);
  }
  HttpServer server = StartHttpServerOrFail({"--workers=1", "--auth_tokens_file=" + tokens_file});
  ASSERT_NE(server.process, nullptr);
  const int port = server.http_port;
  const std::string request = RequestJson(RequestFor(NotchMesh(), 10));

  HttpAnswer answer = HttpPost(port, "/v1/jobs", request);
  EXPECT_EQ(answer.status, 401);
  EXPECT_EQ(ErrorOf(answer).status, "UNAUTHENTICATED");
  EXPECT_EQ(HttpPost(port, "/v1/jobs", request, "wrong-token").status, 401);
  EXPECT_EQ(HttpGet(port, "/v1/jobs").status, 401);

  answer = HttpPost(port, "/v1/jobs", request, "alice-token-0123");
  ASSERT_EQ(answer.status, 200) << answer.body;
  const v1::Job job = FromJson<v1::Job>(answer.body);
  EXPECT_EQ(job.owner(), "alice");
  EXPECT_EQ(HttpGet(port, JobPath(job.name()), "alice-token-0123").status, 200);
  // Bob gets NOT_FOUND, as for a job that never existed, and does not see it listed.
  EXPECT_EQ(HttpGet(port, JobPath(job.name()), "bob-token-4567").status, 404);
  EXPECT_EQ(HttpPost(port, JobPath(job.name(), ":cancel"), "", "bob-token-4567").status, 404);
  answer = HttpGet(port, "/v1/jobs", "bob-token-4567");
  ASSERT_EQ(answer.status, 200);
  EXPECT_EQ(FromJson<v1::ListJobsResponse>(answer.body).jobs_size(), 0);
  // The event stream takes the token from the query too (a browser's EventSource sends no
  // headers).
  const SseStream refused = ReadEventStream(port, JobPath(job.name(), ":watch"));
  EXPECT_EQ(refused.status, 401);
  const SseStream watched =
      ReadEventStream(port, JobPath(job.name(), ":watch?access_token=alice-token-0123"));
  EXPECT_EQ(watched.status, 200);
  const std::vector<v1::QuantizeEvent> events = EventsOf(watched);
  ASSERT_FALSE(events.empty());
  ASSERT_TRUE(events.back().has_result());
  EXPECT_TRUE(IsValidResult(NotchMesh(), events.back().result()));

  // Probes and metrics stay open, as gRPC's health service does.
  EXPECT_EQ(HttpGet(port, "/healthz").status, 200);
  EXPECT_EQ(HttpGet(port, "/metrics").status, 200);
}

TEST(HttpApiTest, RequestIdMakesRetriesSafeAcrossTransports) {
  HttpServer server = StartHttpServerOrFail({"--workers=1"});
  ASSERT_NE(server.process, nullptr);
  client::QuantizerClient grpc_client = ClientOf(*server.process);
  v1::QuantizeRequest request = RequestFor(NotchMesh(), 25);
  request.set_request_id("http-retry-0001");

  const HttpAnswer first = HttpPost(server.http_port, "/v1/jobs", RequestJson(request));
  ASSERT_EQ(first.status, 200) << first.body;
  const HttpAnswer again = HttpPost(server.http_port, "/v1/jobs", RequestJson(request));
  ASSERT_EQ(again.status, 200) << again.body;
  EXPECT_EQ(FromJson<v1::Job>(again.body).name(), FromJson<v1::Job>(first.body).name());
  // The same id over gRPC finds the same job: one service, one table of ids.
  const absl::StatusOr<v1::Job> over_grpc = grpc_client.SubmitJob(request);
  ASSERT_TRUE(over_grpc.ok()) << over_grpc.status();
  EXPECT_EQ(over_grpc->name(), FromJson<v1::Job>(first.body).name());

  request.mutable_options()->mutable_scaling()->set_level_percent(50);
  const HttpAnswer conflict = HttpPost(server.http_port, "/v1/jobs", RequestJson(request));
  EXPECT_EQ(conflict.status, 409);
  EXPECT_EQ(ErrorOf(conflict).status, "ALREADY_EXISTS");
}

}  // namespace
}  // namespace ispq::testing
