// SPDX-License-Identifier: Apache-2.0
// The plain data a TMesh is built from (core/tmesh_builder.h), one struct per element of the format
// (proto/README.md), already decoded: directions are Dir, corners and edges are indexed by their
// codes (core/direction.h), transitions are Rotations. What the model does not keep (node
// positions, transition translations, the arcs and nodes inside block faces, the file's statistics)
// has no field here; whoever decodes a file checks it.
//
// Lists are views into the caller's storage (a message's repeated fields, for instance) that
// only need to live through the Add call that takes them. What a struct cannot say is the
// decoder's to guarantee: every id is in range for the builder's TMeshSizes (so that nothing
// downstream indexes with a hostile id), each block lists each edge code once, and every block
// edge and face lists something. Every other rule is the builder's to check.
#ifndef ISPQ_CORE_TMESH_INPUT_H_
#define ISPQ_CORE_TMESH_INPUT_H_

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/direction.h"
#include "core/rotation.h"
#include "core/tmesh.h"

namespace ispq {

struct TMeshSizes {
  int nodes = 0;
  int arcs = 0;
  int patches = 0;
  int blocks = 0;
};

// Which kinds of feature markers the source had; the critical-node rules depend on it.
struct FeaturesPresent {
  bool nodes = false;
  bool arcs = false;
  bool patches = false;
};

struct TMeshHeader {
  std::string name;
  TMeshSizes sizes;
  FeaturesPresent features_present;
};

struct NodeInput {
  std::span<const HalfarcId> outgoing_halfarcs;
  bool critical = false;
  bool feature = false;
  bool boundary = false;
  SingularType singular_type = SingularType::kRegular;
  FeatureType feature_type = FeatureType::kRegular;
};

struct ArcInput {
  NodeId from = kNoId;
  NodeId to = kNoId;
  double length = 0;  // unscaled, any double: the builder checks it is positive and finite
  int singular = 0;   // wider than the model's mark, so that an out-of-range value is seen
  bool feature = false;
  bool boundary = false;
  bool critical = false;
  std::span<const HalfpatchId> halfpatches;  // whose cycle contains halfarc 2a, radial order
};

// One straight side of a patch: the halfarcs of its cycle along `dir` in the reference block.
struct PatchSideInput {
  Dir dir = Dir::kPosU;
  std::span<const HalfarcId> halfarcs;
};

struct PatchInput {
  std::array<BlockId, 2> blocks = {kNoId, kNoId};            // kNoId on a boundary side
  std::array<Dir, 2> face_sides = {Dir::kPosU, Dir::kPosU};  // where blocks[k] exists
  Rotation rotation;  // from the frame of blocks[0] to the frame of blocks[1]
  bool feature = false;
  bool boundary = false;
  bool critical = false;
  std::span<const HalfarcId> cycle;  // closed cycle of halfpatch 2p
  BlockId ref_block = kNoId;
  std::array<PatchSideInput, 4> sides;
};

// The arcs of a block edge from its NEG to its POS end, and the same arcs as halfarcs running
// along the positive axis (equal lengths, arcs[i] == ArcOf(halfarcs[i])).
struct BlockEdgeInput {
  std::span<const ArcId> arcs;
  std::span<const HalfarcId> halfarcs;
};

struct BlockInput {
  std::array<NodeId, kNumCorners> corners = {};  // by corner code
  std::array<BlockEdgeInput, kNumEdges> edges;   // by edge code
  // The edge codes in the order the source lists the edges: edge rules are checked in this
  // order, so that the source's first broken edge is the one reported.
  std::array<int8_t, kNumEdges> edge_order = {};
  std::array<std::span<const PatchId>, kNumDirs> face_patches;  // by DirIndex of the side
  std::span<const HalfpatchId> halfpatches;
  std::vector<BlockArc> arcs;          // every arc on the boundary, any order
  std::vector<BlockNodeUvw> node_uvw;  // every node on the boundary, any order
};

}  // namespace ispq

#endif  // ISPQ_CORE_TMESH_INPUT_H_
