// SPDX-License-Identifier: Apache-2.0
// A unary call with arbitrary bytes as the request, for hostile requests that the typed client
// cannot express (wire-format tricks, requests larger than building them as messages would
// allow), with the status and the trailers that came back.
#ifndef ISPQ_TESTS_INTEGRATION_RAW_CALL_H_
#define ISPQ_TESTS_INTEGRATION_RAW_CALL_H_

#include <map>
#include <memory>
#include <string>

#include "absl/time/time.h"
#include "grpcpp/channel.h"
#include "grpcpp/support/status.h"

namespace ispq::testing {

struct RawCallResult {
  grpc::Status status;
  std::string response;
  std::multimap<std::string, std::string> trailers;
};

// Calls `method` (e.g. "/ispq.v1.Quantizer/SubmitJob") with `request` as its request bytes.
RawCallResult RawUnaryCall(const std::shared_ptr<grpc::Channel>& channel, const std::string& method,
                           const std::string& request, absl::Duration timeout);

// A length-delimited protobuf field: tag, varint length, bytes.
std::string LengthDelimited(int field, const std::string& bytes);

}  // namespace ispq::testing

#endif  // ISPQ_TESTS_INTEGRATION_RAW_CALL_H_
