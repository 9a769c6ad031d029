// SPDX-License-Identifier: Apache-2.0
#include "core/tmesh_builder.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "core/status_macros.h"
#include "core/tmesh_criticality_checks.h"
#include "core/tmesh_element_checks.h"
#include "core/tmesh_frame_checks.h"
#include "core/tmesh_incidence_checks.h"
#include "core/tmesh_patch_checks.h"

namespace ispq {

absl::StatusOr<TMeshBuilder> TMeshBuilder::Create(const TMeshHeader& header,
                                                  const TMeshValidationOptions& options) {
  ISPQ_RETURN_IF_ERROR(CheckSizes(header.sizes));
  return TMeshBuilder(header, options);
}

TMeshBuilder::TMeshBuilder(const TMeshHeader& header, const TMeshValidationOptions& options)
    : sizes_(header.sizes), features_(header.features_present), options_(options) {
  mesh_.name_ = header.name;
  mesh_.features_present_ = features_.nodes || features_.arcs || features_.patches;
  SizeArrays();
}

// The per-element arrays get their final size at once (the sizes are bounded by the input), so
// elements are written in place; the lists grow as elements are added.
void TMeshBuilder::SizeArrays() {
  const int n = sizes_.nodes, a = sizes_.arcs, p = sizes_.patches;
  mesh_.node_critical_.resize(n);
  mesh_.node_feature_.resize(n);
  mesh_.arc_from_.resize(a);
  mesh_.arc_to_.resize(a);
  mesh_.arc_length_.resize(a);
  mesh_.arc_singular_.resize(a);
  mesh_.arc_feature_.resize(a);
  mesh_.arc_boundary_.resize(a);
  mesh_.arc_critical_.resize(a);
  mesh_.patch_blocks_.resize(p);
  mesh_.patch_face_sides_.resize(p);
  mesh_.patch_rotation_.resize(p);
  mesh_.patch_feature_.resize(p);
  mesh_.patch_boundary_.resize(p);
  mesh_.patch_critical_.resize(p);
  mesh_.patch_ref_block_.resize(p);
  mesh_.patch_side_dir_.resize(p);
  mesh_.block_corners_.resize(sizes_.blocks);
}

absl::Status TMeshBuilder::Expect(Stage stage) const {
  if (stage_ != stage) {
    return absl::FailedPreconditionError(
        "TMeshBuilder: add nodes, arcs, patches and blocks in id order, then Connect, "
        "DeriveCriticalEntities, AddLevel and Build");
  }
  return absl::OkStatus();
}

void TMeshBuilder::Advance(int added, int size) {
  next_ = added;
  if (added == size) {
    stage_ = static_cast<Stage>(static_cast<int>(stage_) + 1);
    next_ = 0;
  }
}

absl::Status TMeshBuilder::AddNode(const NodeInput& node) {
  ISPQ_RETURN_IF_ERROR(Expect(Stage::kNodes));
  const NodeId n = next_;
  ISPQ_RETURN_IF_ERROR(CheckNode(n, node, features_));
  mesh_.node_outgoing_.Append(node.outgoing_halfarcs);
  mesh_.node_critical_[n] = node.critical;
  mesh_.node_feature_[n] = node.feature;
  node_types_.push_back({node.singular_type, node.feature_type});
  Advance(n + 1, sizes_.nodes);
  return absl::OkStatus();
}

absl::Status TMeshBuilder::AddArc(const ArcInput& arc) {
  ISPQ_RETURN_IF_ERROR(Expect(Stage::kArcs));
  const ArcId a = next_;
  ISPQ_RETURN_IF_ERROR(CheckArc(a, arc, features_));
  mesh_.arc_from_[a] = arc.from;
  mesh_.arc_to_[a] = arc.to;
  mesh_.arc_length_[a] = arc.length;
  mesh_.arc_singular_[a] = static_cast<int8_t>(arc.singular);  // in -4..4 (CheckArc)
  mesh_.arc_feature_[a] = arc.feature;
  mesh_.arc_boundary_[a] = arc.boundary;
  mesh_.arc_critical_[a] = arc.critical;
  mesh_.arc_halfpatches_.Append(arc.halfpatches);
  Advance(a + 1, sizes_.arcs);
  return absl::OkStatus();
}

absl::Status TMeshBuilder::AddPatch(const PatchInput& patch) {
  ISPQ_RETURN_IF_ERROR(Expect(Stage::kPatches));
  const PatchId p = next_;
  ISPQ_RETURN_IF_ERROR(CheckPatch(p, patch, mesh_, features_, options_.length_tolerance));
  mesh_.patch_blocks_[p] = patch.blocks;
  mesh_.patch_face_sides_[p] = patch.face_sides;
  mesh_.patch_rotation_[p] = patch.rotation;
  mesh_.patch_feature_[p] = patch.feature;
  mesh_.patch_boundary_[p] = patch.boundary;
  mesh_.patch_critical_[p] = patch.critical;
  mesh_.patch_cycle_.Append(patch.cycle);
  mesh_.patch_ref_block_[p] = patch.ref_block;
  for (int i = 0; i < 4; ++i) {
    mesh_.patch_side_dir_[p][i] = patch.sides[i].dir;
    mesh_.patch_side_halfarcs_.Append(patch.sides[i].halfarcs);
  }
  Advance(p + 1, sizes_.patches);
  return absl::OkStatus();
}

absl::Status TMeshBuilder::AddBlock(BlockInput block) {
  ISPQ_RETURN_IF_ERROR(Expect(Stage::kBlocks));
  const BlockId b = next_;
  std::sort(block.arcs.begin(), block.arcs.end(),
            [](const BlockArc& x, const BlockArc& y) { return x.arc < y.arc; });
  std::sort(block.node_uvw.begin(), block.node_uvw.end(),
            [](const BlockNodeUvw& x, const BlockNodeUvw& y) { return x.node < y.node; });
  ISPQ_RETURN_IF_ERROR(CheckBlock(b, block));
  mesh_.block_corners_[b] = block.corners;
  for (const BlockEdgeInput& edge : block.edges) {
    mesh_.block_edge_arcs_.Append(edge.arcs);
    edge_halfarcs_.Append(edge.halfarcs);
  }
  edge_order_.insert(edge_order_.end(), block.edge_order.begin(), block.edge_order.end());
  for (const std::span<const PatchId> face : block.face_patches) {
    mesh_.block_face_patches_.Append(face);
  }
  mesh_.block_halfpatches_.Append(block.halfpatches);
  mesh_.block_arcs_.Append(block.arcs);
  mesh_.block_node_uvw_.Append(block.node_uvw);
  Advance(b + 1, sizes_.blocks);
  return absl::OkStatus();
}

absl::Status TMeshBuilder::Connect() {
  ISPQ_RETURN_IF_ERROR(Expect(Stage::kConnect));
  ISPQ_RETURN_IF_ERROR(CheckNodeArcIncidence(mesh_));
  ISPQ_RETURN_IF_ERROR(CheckArcPatchIncidence(mesh_));
  ISPQ_RETURN_IF_ERROR(CheckPatchBlockIncidence(mesh_));
  ISPQ_RETURN_IF_ERROR(CheckPatchFrames(mesh_));
  ISPQ_RETURN_IF_ERROR(CheckBlockEdgeChains(mesh_, edge_halfarcs_, edge_order_));
  ISPQ_RETURN_IF_ERROR(CheckBlockCoordinates(mesh_, options_.length_tolerance));
  DeriveNodeAdjacency();
  DeriveArcBlocks();
  ISPQ_RETURN_IF_ERROR(CheckArcBlocks(mesh_));
  // Arc singularity reads arc_blocks; the node rules read the checked singular marks.
  ISPQ_RETURN_IF_ERROR(CheckArcSingularity(mesh_));
  ISPQ_RETURN_IF_ERROR(CheckNodeTypes(mesh_, node_types_));
  ISPQ_RETURN_IF_ERROR(CheckCriticalNodes(mesh_, features_));
  stage_ = Stage::kEntities;
  return absl::OkStatus();
}

// Nodes -> blocks from the blocks' arcs, nodes -> halfpatches from the cycles; both ascending.
void TMeshBuilder::DeriveNodeAdjacency() {
  std::vector<std::vector<BlockId>> node_blocks(sizes_.nodes);
  for (BlockId b = 0; b < sizes_.blocks; ++b) {
    for (const BlockArc& ba : mesh_.block_arcs(b)) {
      node_blocks[mesh_.arc_from(ba.arc)].push_back(b);
      node_blocks[mesh_.arc_to(ba.arc)].push_back(b);
    }
  }
  for (auto& list : node_blocks) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    mesh_.node_blocks_.Append(list);
  }
  std::vector<std::vector<HalfpatchId>> node_halfpatches(sizes_.nodes);
  for (PatchId p = 0; p < sizes_.patches; ++p) {
    for (HalfarcId h : mesh_.patch_cycle(p)) {
      node_halfpatches[mesh_.tail(h)].push_back(2 * p);
      node_halfpatches[mesh_.tail(h)].push_back(2 * p + 1);
    }
  }
  for (auto& list : node_halfpatches) {
    std::sort(list.begin(), list.end());
    mesh_.node_halfpatches_.Append(list);
  }
}

// Arcs -> blocks in the radial order of their halfpatches, each block once.
void TMeshBuilder::DeriveArcBlocks() {
  std::vector<BlockId> radial;
  for (ArcId a = 0; a < sizes_.arcs; ++a) {
    radial.clear();
    for (HalfpatchId hp : mesh_.arc_halfpatches(a)) {
      const BlockId b = mesh_.halfpatch_block(hp);
      if (b != kNoId && std::find(radial.begin(), radial.end(), b) == radial.end()) {
        radial.push_back(b);
      }
    }
    mesh_.arc_blocks_.Append(radial);
  }
}

absl::Status TMeshBuilder::DeriveCriticalEntities(std::span<const CriticalEntity> listed) {
  ISPQ_RETURN_IF_ERROR(Expect(Stage::kEntities));
  const std::vector<CriticalEntity> derived = ispq::DeriveCriticalEntities(mesh_);
  ISPQ_RETURN_IF_ERROR(CheckListedCriticalEntities(derived, listed));
  for (const CriticalEntity& entity : derived) {
    mesh_.entity_dim_.push_back(entity.dim);
    mesh_.entity_nodes_.push_back({entity.node_from, entity.node_to});
    mesh_.entity_halfarcs_.Append(entity.halfarcs);
    mesh_.entity_patches_.Append(entity.patches);
  }
  stage_ = Stage::kLevels;
  return absl::OkStatus();
}

absl::Status TMeshBuilder::AddLevel(const Level& level) {
  ISPQ_RETURN_IF_ERROR(Expect(Stage::kLevels));
  ISPQ_RETURN_IF_ERROR(
      CheckLevel(static_cast<int>(mesh_.levels_.size()), level, mesh_.arc_lengths()));
  mesh_.levels_.push_back(level);
  return absl::OkStatus();
}

absl::StatusOr<TMesh> TMeshBuilder::Build() && {
  ISPQ_RETURN_IF_ERROR(Expect(Stage::kLevels));
  return std::move(mesh_);
}

}  // namespace ispq
