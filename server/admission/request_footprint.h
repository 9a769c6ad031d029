// SPDX-License-Identifier: Apache-2.0
// What a request will cost before it is parsed: a walk over its wire format that estimates the
// heap that parsing it would allocate, and refuses strings longer than the server accepts.
//
// Parsing amplifies: an empty repeated message is 2 bytes on the wire and a hundred in memory,
// so a 32 MiB request of empty nodes parses into more than a gigabyte. The walk reads the bytes
// once without allocating anything from them, so the server can reserve the parsed size in its
// memory budget (or refuse the request) first. The estimate follows protobuf's C++ layout: the
// generated class size of every message, the pointer slots of repeated fields with their growth,
// string objects and their contents, unknown fields, plus the allocator's per-block overhead. It
// errs on the high side (tests/server compares it with protobuf's own SpaceUsedLong).
#ifndef ISPQ_SERVER_ADMISSION_REQUEST_FOOTPRINT_H_
#define ISPQ_SERVER_ADMISSION_REQUEST_FOOTPRINT_H_

#include <cstdint>

#include "absl/status/statusor.h"
#include "google/protobuf/descriptor.h"
#include "server/admission/request_bytes.h"

namespace ispq::server {

// Longest string field of a request (names, ids, a mesh's source): far above any real one.
inline constexpr int kMaxRequestStringBytes = 1024;

// The estimated parsed size of `raw` as a `type` message. INVALID_ARGUMENT naming the field for a
// string field longer than `max_string_bytes`, and for bytes that are not a `type` message.
absl::StatusOr<int64_t> EstimateParsedBytes(const google::protobuf::Descriptor& type,
                                            const RequestBytes& raw,
                                            int max_string_bytes = kMaxRequestStringBytes);

}  // namespace ispq::server

#endif  // ISPQ_SERVER_ADMISSION_REQUEST_FOOTPRINT_H_
