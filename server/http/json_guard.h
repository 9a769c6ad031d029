// SPDX-License-Identifier: Apache-2.0
// What a JSON request body must be before protobuf's JSON parser sees it. That parser recurses
// once per level of nesting and builds its own tree of what it reads, so a body of a few MB of
// `[` costs hundreds of MB and much stack before it is refused; it also takes raw NUL bytes and
// duplicate keys (the last one wins) without a word. This check reads the body once, with memory
// in proportion to the nesting depth and the keys of the open objects, and refuses (with
// INVALID_ARGUMENT naming the problem and where) a body that:
//
//   * starts with a byte order mark, contains a NUL byte or is not valid UTF-8;
//   * nests objects and arrays deeper than `max_depth`;
//   * repeats a key in one object, counting a field's two spellings in protobuf's JSON
//     ("stored_mesh" and "storedMesh") as the same key, as the parser does (right for messages
//     without map fields, which the API's requests have none of).
//
// Anything else it leaves to the parser, whose messages name the problem better (malformed JSON,
// unknown fields, wrong types).
#ifndef ISPQ_SERVER_HTTP_JSON_GUARD_H_
#define ISPQ_SERVER_HTTP_JSON_GUARD_H_

#include "absl/status/status.h"
#include "absl/strings/string_view.h"

namespace ispq::server::http {

inline constexpr int kMaxJsonDepth = 64;  // the API's requests nest 5 levels deep

absl::Status CheckJsonBody(absl::string_view body, int max_depth = kMaxJsonDepth);

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_JSON_GUARD_H_
