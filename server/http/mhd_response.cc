// SPDX-License-Identifier: Apache-2.0
#include "server/http/mhd_response.h"

#include <microhttpd.h>
#include <sys/socket.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "server/http/http_status.h"

namespace ispq::server::http {
namespace {

// How much of a streamed body libmicrohttpd asks for at once.
constexpr size_t kStreamBlockBytes = 16 << 10;

// A held body and what it owns, freed by libmicrohttpd's callback once sent.
struct HeldBody {
  std::string body;
  MemoryReservation memory;
};

void FreeHeldBody(void* held) { delete static_cast<HeldBody*>(held); }

// A streamed body as libmicrohttpd reads it: the bytes it produced last are handed out in as
// many pieces as the connection takes, accounted in the budget until then.
class StreamedResponse : public StreamConnection {
 public:
  StreamedResponse(MHD_Connection* connection, std::unique_ptr<StreamedBody> body,
                   MemoryBudget& budget, Suspensions& suspensions)
      : connection_(connection),
        body_(std::move(body)),
        budget_(budget),
        suspensions_(suspensions) {}

  ssize_t Read(char* buffer, size_t max) {
    if (offset_ == pending_.size()) {
      if (last_) return MHD_CONTENT_READER_END_OF_STREAM;
      pending_.clear();
      offset_ = 0;
      in_flight_.Release();
      const StreamedBody::Step step = body_->Produce(pending_, *this);
      if (step == StreamedBody::Step::kAbort) return MHD_CONTENT_READER_END_WITH_ERROR;
      last_ = step == StreamedBody::Step::kLast;
      if (pending_.empty()) return last_ ? MHD_CONTENT_READER_END_OF_STREAM : 0;  // suspended
      in_flight_ =
          budget_.ForceReserve(MemoryUse::kResponses, static_cast<int64_t>(pending_.size()));
    }
    const size_t length = std::min(max, pending_.size() - offset_);
    std::memcpy(buffer, pending_.data() + offset_, length);
    offset_ += length;
    return static_cast<ssize_t>(length);
  }

  void Suspend() override { suspensions_.Suspend(connection_); }
  void Resume() override { suspensions_.Resume(connection_); }

 private:
  MHD_Connection* const connection_;
  const std::unique_ptr<StreamedBody> body_;
  MemoryBudget& budget_;
  Suspensions& suspensions_;
  std::string pending_;
  size_t offset_ = 0;
  bool last_ = false;
  MemoryReservation in_flight_;
};

ssize_t ReadStream(void* stream, uint64_t /*position*/, char* buffer, size_t max) {
  return static_cast<StreamedResponse*>(stream)->Read(buffer, max);
}

void FreeStream(void* stream) { delete static_cast<StreamedResponse*>(stream); }

MHD_Response* Create(MHD_Connection* connection, HttpResponse& response, MemoryBudget& budget,
                     Suspensions& suspensions) {
  if (response.stream != nullptr) {
    auto* stream =
        new StreamedResponse(connection, std::move(response.stream), budget, suspensions);
    MHD_Response* mhd = MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, kStreamBlockBytes,
                                                          &ReadStream, stream, &FreeStream);
    if (mhd == nullptr) delete stream;
    return mhd;
  }
  if (response.body.empty()) {
    // Static data (the web view's files) or nothing: no copy, nothing to free.
    return MHD_create_response_from_buffer(response.static_body.size(),
                                           const_cast<char*>(response.static_body.data()),
                                           MHD_RESPMEM_PERSISTENT);
  }
  auto* held = new HeldBody{std::move(response.body), std::move(response.memory)};
  MHD_Response* mhd = MHD_create_response_from_buffer_with_free_callback_cls(
      held->body.size(), held->body.data(), &FreeHeldBody, held);
  if (mhd == nullptr) delete held;
  return mhd;
}

}  // namespace

bool QueueResponse(MHD_Connection* connection, HttpResponse response, MemoryBudget& budget,
                   Suspensions& suspensions) {
  MHD_Response* const mhd = Create(connection, response, budget, suspensions);
  if (mhd == nullptr) return false;
  if (!response.content_type.empty()) {
    MHD_add_response_header(mhd, MHD_HTTP_HEADER_CONTENT_TYPE, response.content_type.c_str());
  }
  for (const auto& [name, value] : response.headers) {
    MHD_add_response_header(mhd, name.c_str(), value.c_str());
  }
  const bool queued =
      MHD_queue_response(connection, static_cast<unsigned>(response.status), mhd) == MHD_YES;
  MHD_destroy_response(mhd);  // the connection holds it now, if it took it
  return queued;
}

void WriteRefusal(MHD_Connection* connection, const absl::Status& status) {
  const MHD_ConnectionInfo* info =
      MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CONNECTION_FD);
  if (info == nullptr) return;
  const int code = HttpStatusOf(status);
  const std::string body = ErrorJson(status);
  std::string text =
      absl::StrCat("HTTP/1.1 ", code, " ", MHD_get_reason_phrase_for(code),
                   "\r\nContent-Type: application/json\r\nContent-Length: ", body.size(),
                   "\r\nConnection: close\r\n");
  if (const std::optional<std::string> retry = RetryAfterSeconds(status); retry.has_value()) {
    absl::StrAppend(&text, "Retry-After: ", *retry, "\r\n");
  }
  absl::StrAppend(&text, "\r\n", body);
  // Best effort: a socket whose buffer is full gets only the close.
  (void)send(info->connect_fd, text.data(), text.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

}  // namespace ispq::server::http
