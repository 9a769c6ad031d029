// SPDX-License-Identifier: Apache-2.0
#include "tests/integration/http_test_support.h"

#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "absl/time/clock.h"
#include "tests/integration/http_client.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/bounded_wait.h"

namespace ispq::testing {
namespace {

HttpHeaderList HeadersWith(const std::string& token) {
  HttpHeaderList headers;
  if (!token.empty()) headers.emplace_back("Authorization", absl::StrCat("Bearer ", token));
  return headers;
}

HttpAnswer AnswerOf(const HttpReply& reply) {
  HttpAnswer answer;
  answer.status = reply.status;
  answer.body = reply.body;
  answer.content_type = reply.Header("Content-Type");
  answer.retry_after = reply.Header("Retry-After");
  return answer;
}

// Parses complete frames (ended by a blank line) off the front of `buffer`.
void TakeFrames(std::string& buffer, std::vector<SseFrame>& frames) {
  size_t end = 0;
  while ((end = buffer.find("\n\n")) != std::string::npos) {
    SseFrame frame;
    bool any_field = false;
    for (absl::string_view line : absl::StrSplit(buffer.substr(0, end), '\n')) {
      if (line.empty() || line.front() == ':') continue;  // comments (keepalives)
      const size_t colon = line.find(':');
      const absl::string_view field = line.substr(0, colon);
      absl::string_view value = colon == absl::string_view::npos ? "" : line.substr(colon + 1);
      absl::ConsumePrefix(&value, " ");
      if (field == "id") frame.id = std::string(value);
      if (field == "event") frame.event = std::string(value);
      if (field == "data") absl::StrAppend(&frame.data, frame.data.empty() ? "" : "\n", value);
      any_field = any_field || field == "data" || field == "id" || field == "event";
    }
    buffer.erase(0, end + 2);
    if (any_field && (!frame.data.empty() || !frame.event.empty())) frames.push_back(frame);
  }
}

}  // namespace

HttpServer StartHttpServerOrFail(const std::vector<std::string>& flags) {
  HttpServer server;
  char directory[] = "/tmp/ispq-http-test-XXXXXX";
  if (mkdtemp(directory) == nullptr) {
    ADD_FAILURE() << "mkdtemp failed";
    return server;
  }
  const std::string port_file = absl::StrCat(directory, "/http_port");
  std::vector<std::string> all = flags;
  all.push_back("--http_listen=127.0.0.1:0");
  all.push_back(absl::StrCat("--http_port_file=", port_file));
  server.process = StartServerOrFail(all);
  if (server.process == nullptr) return server;
  // Written right after the gRPC port file (bounded only against a hang).
  const absl::Time deadline = absl::Now() + kSafetyNet;
  while (absl::Now() < deadline) {
    std::ifstream in(port_file);
    int port = 0;
    if (in >> port && port > 0) {
      server.http_port = port;
      break;
    }
    absl::SleepFor(absl::Milliseconds(20));
  }
  std::filesystem::remove_all(directory);
  if (server.http_port == 0) {
    ADD_FAILURE() << "the server wrote no HTTP port; its log:\n" << server.process->Log();
    server.process.reset();
  }
  return server;
}

HttpAnswer HttpGet(int port, const std::string& path, const std::string& token) {
  return AnswerOf(SendHttpRequest(port, "GET", path, HeadersWith(token), "", absl::Seconds(120)));
}

HttpAnswer HttpPost(int port, const std::string& path, const std::string& body,
                    const std::string& token) {
  HttpHeaderList headers = HeadersWith(token);
  headers.emplace_back("Content-Type", "application/json");
  return AnswerOf(SendHttpRequest(port, "POST", path, headers, body, absl::Seconds(120)));
}

SseStream ReadEventStream(int port, const std::string& path, const std::string& last_event_id,
                          const std::string& token, int max_frames, absl::Duration timeout) {
  HttpHeaderList headers = HeadersWith(token);
  headers.emplace_back("Accept", "text/event-stream");
  if (!last_event_id.empty()) headers.emplace_back("Last-Event-ID", last_event_id);
  SseStream stream;
  std::string buffer;
  std::string error_body;  // an error answer has a JSON body, not frames
  bool is_error = false;
  const HttpReply reply = SendHttpRequest(
      port, "GET", path, headers, "", timeout,
      [&](absl::string_view data) {
        if (is_error) {
          error_body.append(data.data(), data.size());
          return true;
        }
        buffer.append(data.data(), data.size());
        TakeFrames(buffer, stream.frames);
        return max_frames <= 0 || static_cast<int>(stream.frames.size()) < max_frames;
      },
      [&](const HttpReply& head) { is_error = head.status >= 400; });
  stream.status = reply.status;
  stream.content_type = reply.Header("Content-Type");
  // An error answer is kept as one frame, for its message.
  if (stream.status >= 400) stream.frames.push_back({"", "error", error_body});
  return stream;
}

std::vector<v1::QuantizeEvent> EventsOf(const SseStream& stream) {
  std::vector<v1::QuantizeEvent> events;
  for (const SseFrame& frame : stream.frames) {
    if (frame.event.empty()) events.push_back(FromJson<v1::QuantizeEvent>(frame.data));
  }
  return events;
}

std::string RequestJson(const v1::QuantizeRequest& request) {
  std::string json;
  const auto printed = google::protobuf::util::MessageToJsonString(request, &json);
  EXPECT_TRUE(printed.ok()) << printed.message();
  return json;
}

}  // namespace ispq::testing
