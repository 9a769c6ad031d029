// SPDX-License-Identifier: Apache-2.0
// What the T-mesh decoders read from a message besides its fields: the ids its element counts
// make valid, and its repeated fields as spans. The decoders check every id against an IdRanges
// before handing it on, and hand lists on as views (the builder copies what it keeps).
#ifndef ISPQ_CORE_PROTO_MESSAGE_VIEWS_H_
#define ISPQ_CORE_PROTO_MESSAGE_VIEWS_H_

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/tmesh_input.h"
#include "google/protobuf/repeated_field.h"

namespace ispq {

class IdRanges {
 public:
  explicit IdRanges(const TMeshSizes& sizes) : sizes_(sizes) {}

  bool Node(int64_t n) const { return n >= 0 && n < sizes_.nodes; }
  bool Arc(int64_t a) const { return a >= 0 && a < sizes_.arcs; }
  bool Halfarc(int64_t h) const { return h >= 0 && h < 2 * static_cast<int64_t>(sizes_.arcs); }
  bool Patch(int64_t p) const { return p >= 0 && p < sizes_.patches; }
  bool Halfpatch(int64_t hp) const {
    return hp >= 0 && hp < 2 * static_cast<int64_t>(sizes_.patches);
  }
  bool Block(int64_t b) const { return b >= 0 && b < sizes_.blocks; }

 private:
  TMeshSizes sizes_;
};

// A repeated scalar field as a span; valid while the message is.
template <typename T>
std::span<const T> View(const google::protobuf::RepeatedField<T>& field) {
  return {field.data(), static_cast<size_t>(field.size())};
}

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_MESSAGE_VIEWS_H_
