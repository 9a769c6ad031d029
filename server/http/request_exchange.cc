// SPDX-License-Identifier: Apache-2.0
#include "server/http/request_exchange.h"

#include <utility>

namespace ispq::server::http {

RequestExchange::RequestExchange(MHD_Connection* connection, RequestBody body,
                                 Suspensions& suspensions)
    : connection_(connection), suspensions_(suspensions), body_(std::move(body)) {}

void RequestExchange::Suspend() {
  absl::MutexLock lock(&mutex_);
  if (answered_) return;  // an inline route, or refused while being dispatched
  suspensions_.Suspend(connection_);
  suspended_ = true;
}

void RequestExchange::OnAnswer(std::function<void()> on_answer) {
  absl::MutexLock lock(&mutex_);
  on_answer_ = std::move(on_answer);
}

void RequestExchange::Answer(HttpResponse response) {
  std::function<void()> on_answer;
  {
    absl::MutexLock lock(&mutex_);
    if (answered_) return;
    answered_ = true;
    answer_ = std::move(response);
    on_answer = std::move(on_answer_);
    // The connection cannot close while suspended, so it is still there to resume.
    if (suspended_) suspensions_.Resume(connection_);
    suspended_ = false;
  }
  if (on_answer) on_answer();
}

bool RequestExchange::Answered() const {
  absl::MutexLock lock(&mutex_);
  return answered_;
}

std::optional<HttpResponse> RequestExchange::TakeAnswer() {
  absl::MutexLock lock(&mutex_);
  std::optional<HttpResponse> answer = std::move(answer_);
  answer_.reset();
  return answer;
}

}  // namespace ispq::server::http
