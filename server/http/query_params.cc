// SPDX-License-Identifier: Apache-2.0
#include "server/http/query_params.h"

#include <string>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"

namespace ispq::server::http {

absl::StatusOr<int64_t> IntParam(const HttpRequest& request, const char* name, int64_t fallback,
                                 int64_t minimum, int64_t maximum) {
  if (!request.HasParam(name)) return fallback;
  const std::string text(request.Param(name));
  int64_t value = 0;
  if (!absl::SimpleAtoi(text, &value) || value < minimum || value > maximum) {
    return absl::InvalidArgumentError(absl::StrCat(
        "query parameter ", name, "=", text, " is not an integer from ", minimum, " to ", maximum));
  }
  return value;
}

absl::StatusOr<v1::JobView> ViewParam(const HttpRequest& request) {
  if (!request.HasParam("view")) return v1::JOB_VIEW_UNSPECIFIED;
  const std::string text(request.Param("view"));
  v1::JobView view = v1::JOB_VIEW_UNSPECIFIED;
  if (!v1::JobView_Parse(text, &view) || view == v1::JOB_VIEW_UNSPECIFIED) {
    return absl::InvalidArgumentError(
        absl::StrCat("query parameter view=", text, " is not BASIC or FULL"));
  }
  return view;
}

absl::StatusOr<v1::JobState> StateParam(const HttpRequest& request) {
  if (!request.HasParam("state")) return v1::JOB_STATE_UNSPECIFIED;
  const std::string text(request.Param("state"));
  v1::JobState state = v1::JOB_STATE_UNSPECIFIED;
  if (!v1::JobState_Parse(text, &state) || state == v1::JOB_STATE_UNSPECIFIED) {
    return absl::InvalidArgumentError(absl::StrCat(
        "query parameter state=", text, " is not QUEUED, RUNNING, SUCCEEDED, FAILED or CANCELLED"));
  }
  return state;
}

}  // namespace ispq::server::http
