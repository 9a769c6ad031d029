// SPDX-License-Identifier: Apache-2.0
// The element ids a T-mesh message's counts make valid. The decoders (core/proto/) check every
// id they read against these ranges before handing it on, so that nothing past them indexes out
// of bounds on a hostile message.
#ifndef ISPQ_CORE_PROTO_ID_RANGES_H_
#define ISPQ_CORE_PROTO_ID_RANGES_H_

#include <cstdint>

#include "core/tmesh_input.h"

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

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_ID_RANGES_H_
