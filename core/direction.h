// SPDX-License-Identifier: Apache-2.0
// Axis-aligned directions in a block's (u, v, w) parameter frame.
//
// A direction is one of the six signed axes, encoded as 2 * axis + (negative ? 1 : 0) so that
// the opposite direction is d ^ 1 and the axis is d >> 1. Sets of directions are 6-bit masks.
// Block corners, edges and faces are indexed with small codes defined here as well, so that a
// block stores its 8 corners, 12 edges and 6 faces in fixed-size arrays.
#ifndef ISPQ_CORE_DIRECTION_H_
#define ISPQ_CORE_DIRECTION_H_

#include <array>
#include <cstdint>
#include <optional>
#include <string>

namespace ispq {

enum class Dir : uint8_t { kPosU = 0, kNegU = 1, kPosV = 2, kNegV = 3, kPosW = 4, kNegW = 5 };

inline constexpr int kNumDirs = 6;
inline constexpr std::array<Dir, kNumDirs> kAllDirs = {Dir::kPosU, Dir::kNegU, Dir::kPosV,
                                                       Dir::kNegV, Dir::kPosW, Dir::kNegW};

constexpr int DirIndex(Dir d) { return static_cast<int>(d); }
constexpr int AxisOf(Dir d) { return static_cast<int>(d) >> 1; }
constexpr bool IsNegative(Dir d) { return (static_cast<int>(d) & 1) != 0; }
constexpr Dir Opposite(Dir d) { return static_cast<Dir>(static_cast<int>(d) ^ 1); }
constexpr Dir MakeDir(int axis, bool negative) {
  return static_cast<Dir>(2 * axis + (negative ? 1 : 0));
}
// +1 or -1: the sign of the direction's unit vector component along its axis.
constexpr int SignOf(Dir d) { return IsNegative(d) ? -1 : 1; }

// A set of directions as a bit mask (bit DirIndex(d)).
using DirSet = uint8_t;
constexpr DirSet DirBit(Dir d) { return static_cast<DirSet>(1u << DirIndex(d)); }
constexpr DirSet AxisBits(int axis) { return static_cast<DirSet>(3u << (2 * axis)); }
inline constexpr DirSet kAllDirBits = 0x3f;

const char* DirName(Dir d);  // "POS_U", ...

// Upstream's bit encoding of a single direction (POS_U=1, NEG_U=2, ..., NEG_W=32).
std::optional<Dir> DirFromUpstreamBits(int bits);

// Corner code: bit `axis` set when the corner is on the positive side of that axis.
// 0 is NEG_U_NEG_V_NEG_W, 7 is POS_U_POS_V_POS_W.
inline constexpr int kNumCorners = 8;
inline constexpr int kMinCorner = 0;
inline constexpr int kMaxCorner = 7;
std::optional<int> CornerFromUpstreamBits(int bits);

// Edge code: 4 * running_axis + (first other axis positive) + 2 * (second other axis positive),
// where the other axes are taken in increasing order. E.g. NEG_V_NEG_W (runs along U) is 0.
inline constexpr int kNumEdges = 12;
constexpr int EdgeCode(int running_axis, bool first_other_positive, bool second_other_positive) {
  return 4 * running_axis + (first_other_positive ? 1 : 0) + (second_other_positive ? 2 : 0);
}
constexpr int EdgeAxis(int edge_code) { return edge_code / 4; }
std::optional<int> EdgeFromUpstreamBits(int bits);
// The format's name of an edge: its two face sides, e.g. "NEG_V_NEG_W" for edge 0.
std::string EdgeName(int edge_code);

}  // namespace ispq

#endif  // ISPQ_CORE_DIRECTION_H_
