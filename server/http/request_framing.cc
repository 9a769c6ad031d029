// SPDX-License-Identifier: Apache-2.0
#include "server/http/request_framing.h"

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "absl/algorithm/container.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/string_view.h"
#include "server/http/http_status.h"

namespace ispq::server::http {
namespace {

constexpr int kLengthRequired = 411;
constexpr int kContentTooLarge = 413;
constexpr int kUriTooLong = 414;
constexpr int kUnsupportedMediaType = 415;
constexpr int kHeaderFieldsTooLarge = 431;
constexpr char kProtobufType[] = "application/x-protobuf";

std::vector<absl::string_view> AllOf(const HttpRequest& request, absl::string_view name) {
  std::vector<absl::string_view> values;
  for (const auto& [key, value] : request.headers) {
    if (key == name) values.push_back(value);
  }
  return values;
}

// Refuses any coding but identity: a compressed body would be decoded whole before anything
// could bound it.
absl::Status CheckContentEncoding(const HttpRequest& request) {
  for (absl::string_view header : AllOf(request, "content-encoding")) {
    for (absl::string_view coding : absl::StrSplit(header, ',')) {
      coding = absl::StripAsciiWhitespace(coding);
      if (!coding.empty() && !absl::EqualsIgnoreCase(coding, "identity")) {
        return WithHttpStatus(
            absl::InvalidArgumentError(absl::StrCat("Content-Encoding ", coding.substr(0, 50),
                                                    ": request bodies are taken as sent, never "
                                                    "decompressed; send the JSON uncompressed")),
            kUnsupportedMediaType);
      }
    }
  }
  return absl::OkStatus();
}

// The declared length, if any; all Content-Length lines must agree.
absl::StatusOr<std::optional<int64_t>> DeclaredLength(const HttpRequest& request) {
  std::optional<int64_t> length;
  for (absl::string_view header : AllOf(request, "content-length")) {
    int64_t value = -1;
    if (header.empty() || !absl::c_all_of(header, absl::ascii_isdigit) ||
        !absl::SimpleAtoi(header, &value) || (length.has_value() && *length != value)) {
      return absl::InvalidArgumentError("Content-Length is malformed or given twice differently");
    }
    length = value;
  }
  return length;
}

absl::Status CheckTransferEncoding(const HttpRequest& request, bool declared_length) {
  const std::vector<absl::string_view> codings = AllOf(request, "transfer-encoding");
  if (codings.empty()) return absl::OkStatus();
  if (codings.size() > 1 ||
      !absl::EqualsIgnoreCase(absl::StripAsciiWhitespace(codings.front()), "chunked")) {
    return absl::UnimplementedError(
        "Transfer-Encoding other than chunked: request bodies are never decoded");
  }
  if (declared_length) {
    return absl::InvalidArgumentError("a request has Content-Length or is chunked, not both");
  }
  return absl::OkStatus();
}

absl::Status TooLarge(int64_t max_body_bytes) {
  return WithHttpStatus(absl::ResourceExhaustedError(
                            absl::StrCat("the body is larger than the ", max_body_bytes,
                                         " bytes this server accepts (--max_message_bytes)")),
                        kContentTooLarge);
}

}  // namespace

absl::Status CheckHeadSize(const HeadSize& size, const HttpLimits& limits) {
  if (static_cast<int64_t>(size.target_bytes) > limits.max_target_bytes) {
    return WithHttpStatus(absl::ResourceExhaustedError(
                              absl::StrCat("the request target is longer than the ",
                                           limits.max_target_bytes, " bytes this server accepts")),
                          kUriTooLong);
  }
  if (static_cast<int64_t>(size.header_bytes) > limits.max_header_bytes ||
      static_cast<int>(size.header_count) > limits.max_headers) {
    return WithHttpStatus(
        absl::ResourceExhaustedError(absl::StrCat(
            "the request has more than ", limits.max_headers, " header lines or more than ",
            limits.max_header_bytes, " bytes of them, more than this server accepts")),
        kHeaderFieldsTooLarge);
  }
  return absl::OkStatus();
}

absl::StatusOr<BodyFraming> PlanBody(const HttpRequest& request, int64_t max_body_bytes) {
  if (absl::Status encoding = CheckContentEncoding(request); !encoding.ok()) return encoding;
  absl::StatusOr<std::optional<int64_t>> length = DeclaredLength(request);
  if (!length.ok()) return length.status();
  if (absl::Status transfer = CheckTransferEncoding(request, length->has_value()); !transfer.ok()) {
    return transfer;
  }
  BodyFraming framing;
  framing.chunked = !AllOf(request, "transfer-encoding").empty();
  if (length->has_value()) {
    framing.length = **length;
    if (framing.length > max_body_bytes) return TooLarge(max_body_bytes);
  } else if (!framing.chunked && request.method == "POST") {
    return WithHttpStatus(
        absl::InvalidArgumentError(
            "a POST must say how long its body is (Content-Length, 0 for none) or send it chunked"),
        kLengthRequired);
  }
  return framing;
}

bool IsProtobufBody(const HttpRequest& request) {
  const std::vector<absl::string_view> types = AllOf(request, "content-type");
  return types.size() == 1 &&
         absl::EqualsIgnoreCase(absl::StripAsciiWhitespace(types.front()), kProtobufType);
}

absl::Status CheckJsonContentType(const HttpRequest& request, bool protobuf_too) {
  if (protobuf_too && IsProtobufBody(request)) return absl::OkStatus();
  const std::vector<absl::string_view> types = AllOf(request, "content-type");
  bool json = types.size() == 1;
  if (json) {
    std::vector<absl::string_view> parts = absl::StrSplit(types.front(), ';');
    json = absl::EqualsIgnoreCase(absl::StripAsciiWhitespace(parts.front()), "application/json");
    for (size_t i = 1; i < parts.size() && json; ++i) {
      std::string parameter = absl::AsciiStrToLower(absl::StripAsciiWhitespace(parts[i]));
      parameter.erase(std::remove(parameter.begin(), parameter.end(), ' '), parameter.end());
      json = parameter == "charset=utf-8" || parameter == "charset=\"utf-8\"";
    }
  }
  if (json) return absl::OkStatus();
  return WithHttpStatus(
      absl::InvalidArgumentError(absl::StrCat(
          "Content-Type ", types.empty() ? "missing" : std::string(types.front().substr(0, 100)),
          ": send the body as Content-Type: application/json",
          protobuf_too ? " or application/x-protobuf" : "")),
      kUnsupportedMediaType);
}

}  // namespace ispq::server::http
