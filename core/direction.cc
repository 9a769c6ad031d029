// SPDX-License-Identifier: Apache-2.0
#include "core/direction.h"

namespace ispq {
namespace {

// Upstream bit of direction index d: POS_U=1, NEG_U=2, POS_V=4, ... i.e. 1 << d.
constexpr int UpstreamBit(int axis, bool negative) { return 1 << (2 * axis + (negative ? 1 : 0)); }

// For a 2- or 3-axis composite, decode which axes are present and their signs; nullopt if some
// axis has both signs or the mask has bits outside the six directions.
struct AxisSigns {
  int axes_present = 0;  // bit per axis
  int positive = 0;      // bit per axis
};

std::optional<AxisSigns> DecodeComposite(int bits) {
  if (bits <= 0 || bits > 63) return std::nullopt;
  AxisSigns s;
  for (int axis = 0; axis < 3; ++axis) {
    const bool pos = (bits & UpstreamBit(axis, false)) != 0;
    const bool neg = (bits & UpstreamBit(axis, true)) != 0;
    if (pos && neg) return std::nullopt;
    if (pos || neg) s.axes_present |= 1 << axis;
    if (pos) s.positive |= 1 << axis;
  }
  return s;
}

}  // namespace

const char* DirName(Dir d) {
  static constexpr std::array<const char*, kNumDirs> kNames = {"POS_U", "NEG_U", "POS_V",
                                                               "NEG_V", "POS_W", "NEG_W"};
  return kNames[DirIndex(d)];
}

std::optional<Dir> DirFromUpstreamBits(int bits) {
  for (Dir d : kAllDirs) {
    if (bits == 1 << DirIndex(d)) return d;
  }
  return std::nullopt;
}

std::optional<int> CornerFromUpstreamBits(int bits) {
  const std::optional<AxisSigns> s = DecodeComposite(bits);
  if (!s || s->axes_present != 7) return std::nullopt;
  return s->positive;
}

std::optional<int> EdgeFromUpstreamBits(int bits) {
  const std::optional<AxisSigns> s = DecodeComposite(bits);
  if (!s) return std::nullopt;
  for (int running = 0; running < 3; ++running) {
    if (s->axes_present != (7 & ~(1 << running))) continue;
    const int first = running == 0 ? 1 : 0;
    const int second = running == 2 ? 1 : 2;
    return EdgeCode(running, (s->positive >> first) & 1, (s->positive >> second) & 1);
  }
  return std::nullopt;
}

std::string EdgeName(int edge_code) {
  const int running = EdgeAxis(edge_code);
  const int first = running == 0 ? 1 : 0;
  const int second = running == 2 ? 1 : 2;
  return std::string(DirName(MakeDir(first, (edge_code & 1) == 0))) + "_" +
         DirName(MakeDir(second, (edge_code & 2) == 0));
}

}  // namespace ispq
