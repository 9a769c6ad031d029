// SPDX-License-Identifier: Apache-2.0
// A repeated scalar field of a message as a span, so that the decoders hand lists on as views
// without copying them (the T-mesh builder copies what it keeps).
#ifndef ISPQ_CORE_PROTO_REPEATED_FIELD_SPAN_H_
#define ISPQ_CORE_PROTO_REPEATED_FIELD_SPAN_H_

#include <cstddef>
#include <span>

#include "google/protobuf/repeated_field.h"

namespace ispq {

// Valid while the message is.
template <typename T>
std::span<const T> View(const google::protobuf::RepeatedField<T>& field) {
  return {field.data(), static_cast<size_t>(field.size())};
}

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_REPEATED_FIELD_SPAN_H_
