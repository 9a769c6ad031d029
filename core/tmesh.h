// SPDX-License-Identifier: Apache-2.0
// The validated, immutable T-mesh that every algorithm of ispq reads.
//
// A TMesh is a block decomposition (blocks, patches, arcs, nodes) with a continuous target length
// per arc: what the algorithms read of a `*.tmesh.json` file (proto/README.md), after validation.
// Connectivity lives in flat arrays indexed by integer ids, with implicit twins: halfarc h = 2a + o
// (twin h ^ 1), halfpatch hp = 2p + k (twin hp ^ 1). All adjacency the quantizer and the separation
// search need is precomputed at load time.
//
// TMeshBuilder (core/tmesh_builder.h) is the only code that writes one, after checking every rule;
// so a TMesh that exists is valid. From an ispq.v1 message, use TMeshFromProto
// (core/proto/tmesh_from_proto.h).
#ifndef ISPQ_CORE_TMESH_H_
#define ISPQ_CORE_TMESH_H_

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/direction.h"
#include "core/flat_lists.h"
#include "core/rotation.h"

namespace ispq {

using NodeId = int32_t;
using ArcId = int32_t;
using HalfarcId = int32_t;
using PatchId = int32_t;
using HalfpatchId = int32_t;
using BlockId = int32_t;
using EntityId = int32_t;

inline constexpr int32_t kNoId = -1;

constexpr ArcId ArcOf(HalfarcId h) { return h >> 1; }
constexpr HalfarcId Twin(HalfarcId h) { return h ^ 1; }
constexpr HalfarcId HalfarcOf(ArcId a, bool reversed) { return 2 * a + (reversed ? 1 : 0); }
constexpr PatchId PatchOf(HalfpatchId hp) { return hp >> 1; }
constexpr int SideOf(HalfpatchId hp) { return hp & 1; }

enum class SingularType : uint8_t { kRegular, kSemiSingular, kSingular };
enum class FeatureType : uint8_t { kRegular, kSemiFeature, kFeature, kSemiFeatureSingularBranch };

// An arc on a block's boundary with the direction halfarc 2a runs along in the block's frame.
struct BlockArc {
  ArcId arc;
  Dir dir;
};

// A node on a block's boundary with its continuous coordinates in the block's frame.
struct BlockNodeUvw {
  NodeId node;
  std::array<double, 3> uvw;
};

// One of the four straight sides of a patch: the halfarcs of halfpatch 2p's cycle that run along
// `dir` in the frame of the patch's reference block, in cycle order.
struct PatchSide {
  Dir dir;
  std::span<const HalfarcId> halfarcs;
};

enum class EntityDim : uint8_t { kNode = 0, kLink = 1, kRegion = 2 };

struct Level {
  int percent;
  double scaling;
};

class TMesh {
 public:
  TMesh() = default;
  TMesh(TMesh&&) = default;
  TMesh& operator=(TMesh&&) = default;
  TMesh(const TMesh&) = delete;
  TMesh& operator=(const TMesh&) = delete;

  // ---- Metadata ----
  const std::string& name() const { return name_; }
  // Whether feature markers existed in the input (the critical-node rules depend on it).
  bool features_present() const { return features_present_; }

  int num_nodes() const { return static_cast<int>(node_critical_.size()); }
  int num_arcs() const { return static_cast<int>(arc_from_.size()); }
  int num_halfarcs() const { return 2 * num_arcs(); }
  int num_patches() const { return static_cast<int>(patch_blocks_.size()); }
  int num_halfpatches() const { return 2 * num_patches(); }
  int num_blocks() const { return static_cast<int>(block_corners_.size()); }
  int num_entities() const { return static_cast<int>(entity_dim_.size()); }

  // ---- Nodes ----
  std::span<const HalfarcId> outgoing_halfarcs(NodeId n) const { return node_outgoing_[n]; }
  bool node_critical(NodeId n) const { return node_critical_[n] != 0; }
  bool node_feature(NodeId n) const { return node_feature_[n] != 0; }
  // Blocks whose boundary contains n, ascending.
  std::span<const BlockId> node_blocks(NodeId n) const { return node_blocks_[n]; }
  // Halfpatches whose cycle passes through n, ascending.
  std::span<const HalfpatchId> node_halfpatches(NodeId n) const { return node_halfpatches_[n]; }

  // ---- Arcs and halfarcs ----
  NodeId arc_from(ArcId a) const { return arc_from_[a]; }
  NodeId arc_to(ArcId a) const { return arc_to_[a]; }
  NodeId tail(HalfarcId h) const { return (h & 1) ? arc_to_[h >> 1] : arc_from_[h >> 1]; }
  NodeId head(HalfarcId h) const { return (h & 1) ? arc_from_[h >> 1] : arc_to_[h >> 1]; }
  // Unscaled continuous target length l_a > 0.
  double arc_length(ArcId a) const { return arc_length_[a]; }
  std::span<const double> arc_lengths() const { return arc_length_; }
  int arc_singular(ArcId a) const { return arc_singular_[a]; }
  bool arc_feature(ArcId a) const { return arc_feature_[a] != 0; }
  bool arc_boundary(ArcId a) const { return arc_boundary_[a] != 0; }
  bool arc_critical(ArcId a) const { return arc_critical_[a] != 0; }
  // Halfpatches whose cycle contains halfarc 2a, in radial order around the arc. Those that
  // contain 2a + 1 are the twins (hp ^ 1) of these.
  std::span<const HalfpatchId> arc_halfpatches(ArcId a) const { return arc_halfpatches_[a]; }
  // Blocks whose boundary contains the arc, in the radial order of arc_halfpatches (each once).
  std::span<const BlockId> arc_blocks(ArcId a) const { return arc_blocks_[a]; }
  // Direction of halfarc h in block b's frame, or nullopt if arc(h) is not on b's boundary.
  std::optional<Dir> HalfarcDirInBlock(HalfarcId h, BlockId b) const;

  // ---- Patches and halfpatches ----
  // Block on side k (halfpatch 2p + k), or kNoId on the boundary.
  BlockId patch_block(PatchId p, int k) const { return patch_blocks_[p][k]; }
  BlockId halfpatch_block(HalfpatchId hp) const { return patch_blocks_[hp >> 1][hp & 1]; }
  // Face side of patch_block(p, k) the patch lies on; only meaningful where that block exists.
  Dir patch_face_side(PatchId p, int k) const { return patch_face_sides_[p][k]; }
  // Rotation from the frame of patch_block(p, 0) to the frame of patch_block(p, 1).
  Rotation patch_rotation(PatchId p) const { return patch_rotation_[p]; }
  // Rotation for crossing halfpatch hp from its block into the block on the twin side.
  Rotation crossing_rotation(HalfpatchId hp) const {
    return (hp & 1) ? patch_rotation_[hp >> 1].Inverse() : patch_rotation_[hp >> 1];
  }
  bool patch_feature(PatchId p) const { return patch_feature_[p] != 0; }
  bool patch_boundary(PatchId p) const { return patch_boundary_[p] != 0; }
  bool patch_critical(PatchId p) const { return patch_critical_[p] != 0; }
  // Closed cycle of halfpatch 2p (normal into patch_block(p, 0)). The cycle of 2p + 1 is this
  // list reversed with every halfarc flipped; HalfpatchCycleAt gives either without copying.
  std::span<const HalfarcId> patch_cycle(PatchId p) const { return patch_cycle_[p]; }
  int halfpatch_cycle_size(HalfpatchId hp) const {
    return static_cast<int>(patch_cycle_[hp >> 1].size());
  }
  HalfarcId HalfpatchCycleAt(HalfpatchId hp, int i) const {
    const std::span<const HalfarcId> cycle = patch_cycle_[hp >> 1];
    if ((hp & 1) == 0) return cycle[i];
    return Twin(cycle[cycle.size() - 1 - i]);
  }
  BlockId patch_ref_block(PatchId p) const { return patch_ref_block_[p]; }
  // Side i in 0..3 of the patch; sides come in upstream enum order of their direction.
  PatchSide patch_side(PatchId p, int i) const {
    return {patch_side_dir_[p][i], patch_side_halfarcs_[4 * p + i]};
  }

  // ---- Blocks ----
  // Corner node by corner code (core/direction.h): 0 = (-,-,-), 7 = (+,+,+).
  NodeId block_corner(BlockId b, int corner) const { return block_corners_[b][corner]; }
  // Arcs of block edge `edge` (edge code, core/direction.h) from the NEG to the POS end.
  std::span<const ArcId> block_edge_arcs(BlockId b, int edge) const {
    return block_edge_arcs_[kNumEdges * b + edge];
  }
  std::span<const PatchId> block_face_patches(BlockId b, Dir side) const {
    return block_face_patches_[kNumDirs * b + DirIndex(side)];
  }
  std::span<const HalfpatchId> block_halfpatches(BlockId b) const { return block_halfpatches_[b]; }
  // Every arc on b's boundary with its direction, ascending by arc id.
  std::span<const BlockArc> block_arcs(BlockId b) const { return block_arcs_[b]; }
  // Every node on b's boundary with its continuous coordinates, ascending by node id.
  std::span<const BlockNodeUvw> block_node_uvw(BlockId b) const { return block_node_uvw_[b]; }

  // ---- Critical entities (nodes, then links, then regions) ----
  EntityDim entity_dim(EntityId e) const { return entity_dim_[e]; }
  NodeId entity_node_from(EntityId e) const { return entity_nodes_[e][0]; }
  NodeId entity_node_to(EntityId e) const { return entity_nodes_[e][1]; }
  std::span<const HalfarcId> entity_halfarcs(EntityId e) const { return entity_halfarcs_[e]; }
  std::span<const PatchId> entity_patches(EntityId e) const { return entity_patches_[e]; }

  // ---- Resolution levels (proto/README.md, section Resolution levels and scaling) ----
  std::span<const Level> levels() const { return levels_; }

 private:
  friend class TMeshBuilder;

  std::string name_;
  bool features_present_ = false;

  FlatLists<HalfarcId> node_outgoing_;
  std::vector<uint8_t> node_critical_, node_feature_;
  FlatLists<BlockId> node_blocks_;
  FlatLists<HalfpatchId> node_halfpatches_;

  std::vector<NodeId> arc_from_, arc_to_;
  std::vector<double> arc_length_;
  std::vector<int8_t> arc_singular_;
  std::vector<uint8_t> arc_feature_, arc_boundary_, arc_critical_;
  FlatLists<HalfpatchId> arc_halfpatches_;
  FlatLists<BlockId> arc_blocks_;

  std::vector<std::array<BlockId, 2>> patch_blocks_;
  std::vector<std::array<Dir, 2>> patch_face_sides_;
  std::vector<Rotation> patch_rotation_;
  std::vector<uint8_t> patch_feature_, patch_boundary_, patch_critical_;
  FlatLists<HalfarcId> patch_cycle_;
  std::vector<BlockId> patch_ref_block_;
  std::vector<std::array<Dir, 4>> patch_side_dir_;
  FlatLists<HalfarcId> patch_side_halfarcs_;  // 4 lists per patch

  std::vector<std::array<NodeId, kNumCorners>> block_corners_;
  FlatLists<ArcId> block_edge_arcs_;       // 12 lists per block
  FlatLists<PatchId> block_face_patches_;  // 6 lists per block
  FlatLists<HalfpatchId> block_halfpatches_;
  FlatLists<BlockArc> block_arcs_;
  FlatLists<BlockNodeUvw> block_node_uvw_;

  std::vector<EntityDim> entity_dim_;
  std::vector<std::array<NodeId, 2>> entity_nodes_;
  FlatLists<HalfarcId> entity_halfarcs_;
  FlatLists<PatchId> entity_patches_;

  std::vector<Level> levels_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_TMESH_H_
