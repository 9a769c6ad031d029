// SPDX-License-Identifier: Apache-2.0
// What the tests of the HTTP side (--http_listen, server/http/) share: a real ispq-server with
// its HTTP listener on a free loopback port, a small JSON client (tests/integration/
// http_client.h), a reader of server-sent-event streams, and protobuf JSON parsing of what the
// server answers.
#ifndef ISPQ_TESTS_INTEGRATION_HTTP_TEST_SUPPORT_H_
#define ISPQ_TESTS_INTEGRATION_HTTP_TEST_SUPPORT_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "google/protobuf/message.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"
#include "tests/integration/server_process.h"

namespace ispq::testing {

// A server with both listeners; `http_port` is the HTTP side's.
struct HttpServer {
  std::unique_ptr<ServerProcess> process;
  int http_port = 0;
};
// Starts ispq-server with `flags` plus --http_listen on a free loopback port; fails the test
// (process null) if it does not come up.
HttpServer StartHttpServerOrFail(const std::vector<std::string>& flags);

struct HttpAnswer {
  int status = 0;  // 0: no answer (connection failed)
  std::string body;
  std::string content_type;
  std::string retry_after;
};

// One request; `token` (if not empty) goes in `Authorization: Bearer`.
HttpAnswer HttpGet(int port, const std::string& path, const std::string& token = "");
HttpAnswer HttpPost(int port, const std::string& path, const std::string& body,
                    const std::string& token = "");

// One server-sent event.
struct SseFrame {
  std::string id;     // empty when the frame had none
  std::string event;  // empty for the default "message"
  std::string data;
};
struct SseStream {
  int status = 0;
  std::string content_type;
  std::vector<SseFrame> frames;
};
// Reads a stream to its end (at most `timeout`); `last_event_id` (if not empty) is sent as
// Last-Event-ID. With `max_frames` > 0, closes the connection after that many frames.
SseStream ReadEventStream(int port, const std::string& path, const std::string& last_event_id = "",
                          const std::string& token = "", int max_frames = 0,
                          absl::Duration timeout = absl::Seconds(300));

// The events (frames without an `event:` type) of a stream, parsed.
std::vector<v1::QuantizeEvent> EventsOf(const SseStream& stream);

// `json` parsed into a `Message`; fails the test if it does not parse.
template <typename Message>
Message FromJson(const std::string& json) {
  Message message;
  const auto parsed = google::protobuf::util::JsonStringToMessage(json, &message);
  EXPECT_TRUE(parsed.ok()) << parsed.message() << " in " << json.substr(0, 500);
  return message;
}

// The QuantizeRequest in protobuf JSON, as a client of the JSON API sends it.
std::string RequestJson(const v1::QuantizeRequest& request);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_INTEGRATION_HTTP_TEST_SUPPORT_H_
