// SPDX-License-Identifier: Apache-2.0
#include "tests/integration/http_client.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/time/clock.h"

namespace ispq::testing {
namespace {

// A connected socket, closed on destruction.
class Socket {
 public:
  Socket(int port, absl::Time deadline) : deadline_(deadline) {
    fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address = {};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (fd_ >= 0 && connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
      close(fd_);
      fd_ = -1;
    }
  }
  ~Socket() {
    if (fd_ >= 0) close(fd_);
  }

  bool ok() const { return fd_ >= 0; }

  // Writes all of `data`; false if the peer stopped taking it (it may have answered already).
  bool Write(absl::string_view data) {
    while (!data.empty()) {
      if (!Wait(POLLOUT)) return false;
      const ssize_t sent = send(fd_, data.data(), data.size(), MSG_NOSIGNAL);
      if (sent <= 0) return false;
      data.remove_prefix(static_cast<size_t>(sent));
    }
    return true;
  }

  // Appends what arrives to `buffer`; false at the end, on an error or at the deadline.
  bool Read(std::string& buffer) {
    if (!Wait(POLLIN)) return false;
    char chunk[16384];
    const ssize_t got = recv(fd_, chunk, sizeof(chunk), 0);
    if (got <= 0) return false;
    buffer.append(chunk, static_cast<size_t>(got));
    return true;
  }

 private:
  bool Wait(short events) {
    const int64_t left = absl::ToInt64Milliseconds(deadline_ - absl::Now());
    if (left <= 0) return false;
    pollfd watched = {.fd = fd_, .events = events, .revents = 0};
    return poll(&watched, 1, static_cast<int>(std::min<int64_t>(left, 1 << 30))) == 1;
  }

  int fd_ = -1;
  const absl::Time deadline_;
};

// Parses the status line and headers off the front of `buffer`; false if incomplete.
bool TakeHead(std::string& buffer, HttpReply& reply) {
  const size_t end = buffer.find("\r\n\r\n");
  if (end == std::string::npos) return false;
  std::vector<std::string> lines = absl::StrSplit(buffer.substr(0, end), "\r\n");
  std::vector<std::string> status = absl::StrSplit(lines.front(), absl::MaxSplits(' ', 2));
  if (status.size() < 2 || !absl::SimpleAtoi(status[1], &reply.status)) reply.status = -1;
  for (size_t i = 1; i < lines.size(); ++i) {
    const size_t colon = lines[i].find(':');
    if (colon == std::string::npos) continue;
    reply.headers.emplace_back(
        lines[i].substr(0, colon),
        std::string(absl::StripAsciiWhitespace(absl::string_view(lines[i]).substr(colon + 1))));
  }
  buffer.erase(0, end + 4);
  return true;
}

// Decodes what is complete of a chunked body at the front of `buffer` into `out`; true once the
// last chunk has been seen.
bool TakeChunks(std::string& buffer, std::string& out) {
  while (true) {
    const size_t line_end = buffer.find("\r\n");
    if (line_end == std::string::npos) return false;
    uint64_t size = 0;
    const std::string size_text = buffer.substr(0, buffer.find_first_of(";\r"));
    if (!absl::SimpleHexAtoi(size_text, &size)) return true;  // malformed: stop
    if (size == 0) return true;
    if (buffer.size() < line_end + 2 + size + 2) return false;
    out.append(buffer, line_end + 2, size);
    buffer.erase(0, line_end + 2 + size + 2);
  }
}

}  // namespace

std::string HttpReply::Header(absl::string_view name) const {
  for (const auto& [key, value] : headers) {
    if (absl::EqualsIgnoreCase(key, name)) return value;
  }
  return "";
}

HttpReply SendHttpRequest(int port, const std::string& method, const std::string& path,
                          const HttpHeaderList& headers, const std::string& body,
                          absl::Duration timeout,
                          const std::function<bool(absl::string_view)>& on_body,
                          const std::function<void(const HttpReply&)>& on_head) {
  HttpReply reply;
  Socket socket(port, absl::Now() + timeout);
  if (!socket.ok()) return reply;
  std::string request = absl::StrCat(method, " ", path, " HTTP/1.1\r\nHost: 127.0.0.1:", port,
                                     "\r\nConnection: close\r\n");
  for (const auto& [name, value] : headers) absl::StrAppend(&request, name, ": ", value, "\r\n");
  if (method == "POST" || !body.empty()) {
    absl::StrAppend(&request, "Content-Length: ", body.size(), "\r\n");
  }
  absl::StrAppend(&request, "\r\n", body);
  socket.Write(request);  // a refusal may come before the body is taken: read it anyway
  std::string buffer;
  while (!TakeHead(buffer, reply)) {
    if (!socket.Read(buffer)) return HttpReply();
  }
  if (on_head != nullptr) on_head(reply);
  const bool chunked = absl::EqualsIgnoreCase(reply.Header("Transfer-Encoding"), "chunked");
  int64_t length = -1;
  if (!absl::SimpleAtoi(reply.Header("Content-Length"), &length)) length = -1;
  std::string decoded;
  bool more = true;
  while (more) {
    bool done = false;
    if (chunked) {
      done = TakeChunks(buffer, decoded);
    } else {
      decoded.append(buffer);
      buffer.clear();
      done = length >= 0 && static_cast<int64_t>(decoded.size()) >= length;
    }
    if (on_body != nullptr && !decoded.empty()) {
      more = on_body(decoded);
      decoded.clear();
    }
    if (done || !more || !socket.Read(buffer)) break;
  }
  if (on_body == nullptr) reply.body = std::move(decoded);
  return reply;
}

}  // namespace ispq::testing
