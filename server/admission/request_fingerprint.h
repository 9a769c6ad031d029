// SPDX-License-Identifier: Apache-2.0
// A fingerprint of a request, to tell a retried SubmitJob (the same request again) from a
// different request that reuses a request_id (server/admission/request_ids.h): the SHA-256 of the
// request's deterministic serialization, computed while serializing without building the bytes.
#ifndef ISPQ_SERVER_ADMISSION_REQUEST_FINGERPRINT_H_
#define ISPQ_SERVER_ADMISSION_REQUEST_FINGERPRINT_H_

#include <string>

#include "google/protobuf/message_lite.h"

namespace ispq::server {

// 32 bytes. Equal for equal messages (unknown fields included), whatever field order the client
// serialized them in.
std::string RequestFingerprint(const google::protobuf::MessageLite& message);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_REQUEST_FINGERPRINT_H_
