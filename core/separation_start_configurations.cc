// SPDX-License-Identifier: Apache-2.0
#include "core/separation_start_configurations.h"

#include <algorithm>

#include "core/halfarc_neighborhood.h"

namespace ispq {
namespace {

Dir DirIn(const TMesh& mesh, HalfarcId h, BlockId b) { return *mesh.HalfarcDirInBlock(h, b); }

// The orthogonal halfarcs bounding one wall (sector) of a link: starting from halfpatch `side`
// around the link's first halfarc, walk along the link through the wall's patches and collect
// at each end of a collinear run the halfarc that leaves the link into the wall. Collinear
// continuations met inside a patch side are appended to `pre_branch_arcs`.
std::vector<HalfarcId> SectorBranchOffs(const TMesh& mesh, std::span<const HalfarcId> link,
                                        const std::vector<uint8_t>& in_link, HalfpatchId side,
                                        std::vector<ArcId>& pre_branch_arcs) {
  const HalfarcId first = link.front();
  std::vector<HalfarcId> branch_offs;

  // Back from the first halfarc to the corner where the collinear run containing it begins.
  BlockId frame = FrameBlockOfHalfpatch(mesh, side);
  const Dir first_dir = DirIn(mesh, first, frame);
  HalfarcId before = PrevInHalfpatch(mesh, side, first);
  while (DirIn(mesh, before, frame) == first_dir) {
    pre_branch_arcs.push_back(ArcOf(before));
    before = PrevInHalfpatch(mesh, side, before);
  }
  branch_offs.push_back(Twin(before));

  HalfarcId current = first;
  HalfpatchId patch_side = side;
  while (true) {
    frame = FrameBlockOfHalfpatch(mesh, patch_side);
    const Dir run_dir = DirIn(mesh, current, frame);
    HalfarcId next = NextInHalfpatch(mesh, patch_side, current);
    while (DirIn(mesh, next, frame) == run_dir) {
      current = next;
      pre_branch_arcs.push_back(ArcOf(current));
      next = NextInHalfpatch(mesh, patch_side, current);
    }
    const HalfarcId orthogonal = next;
    if (std::find(branch_offs.begin(), branch_offs.end(), orthogonal) != branch_offs.end()) break;
    branch_offs.push_back(orthogonal);

    // The neighbouring patch of the same wall: it contains the orthogonal halfarc reversed and
    // continues along the link after it.
    const HalfarcId back = Twin(orthogonal);
    HalfpatchId following = kNoId;
    for (HalfpatchId candidate : HalfpatchesAroundHalfarc(mesh, back)) {
      if (PatchOf(candidate) == PatchOf(patch_side)) continue;
      if (in_link[NextInHalfpatch(mesh, candidate, back)]) {
        following = candidate;
        break;
      }
    }
    if (following == kNoId) break;
    patch_side = following;
    current = NextInHalfpatch(mesh, patch_side, back);
    if (current == first) break;
  }
  return branch_offs;
}

}  // namespace

SeparationStartConfigurations::SeparationStartConfigurations(const TMesh& mesh) {
  std::vector<uint8_t> in_link(mesh.num_halfarcs(), 0);
  for (EntityId e = 0; e < mesh.num_entities(); ++e) {
    switch (mesh.entity_dim(e)) {
      case EntityDim::kNode:
        AddNodeConfigurations(mesh, e);
        break;
      case EntityDim::kLink:
        AddLinkConfigurations(mesh, e, in_link);
        break;
      case EntityDim::kRegion:
        break;  // regions never start a search (core/README.md, section What it looks for)
    }
  }
}

void SeparationStartConfigurations::AddNodeConfigurations(const TMesh& mesh, EntityId e) {
  const NodeId n = mesh.entity_node_from(e);
  const std::span<const HalfarcId> outgoing = mesh.outgoing_halfarcs(n);
  const BlockId start_block = mesh.node_blocks(n).front();
  for (int sector = 0; sector < static_cast<int>(outgoing.size()); ++sector) {
    SeparationStartConfiguration config;
    config.entity = e;
    config.sector = sector;
    config.is_link = false;
    config.start_node = n;
    config.start_block = start_block;
    configs_.push_back(config);
    branch_offs_.Append(std::span<const HalfarcId>(&outgoing[sector], 1));
    pre_branch_arcs_.Append(std::span<const ArcId>());
  }
}

void SeparationStartConfigurations::AddLinkConfigurations(const TMesh& mesh, EntityId e,
                                                          std::vector<uint8_t>& in_link) {
  const std::span<const HalfarcId> link = mesh.entity_halfarcs(e);
  const HalfarcId first = link.front();
  for (HalfarcId h : link) in_link[h] = 1;

  std::vector<ArcId> pre_branch_arcs = {ArcOf(first)};
  std::vector<std::vector<HalfarcId>> sectors;
  for (HalfpatchId side : HalfpatchesAroundHalfarc(mesh, first)) {
    sectors.push_back(SectorBranchOffs(mesh, link, in_link, side, pre_branch_arcs));
  }
  for (HalfarcId h : link) in_link[h] = 0;
  std::sort(pre_branch_arcs.begin(), pre_branch_arcs.end());
  pre_branch_arcs.erase(std::unique(pre_branch_arcs.begin(), pre_branch_arcs.end()),
                        pre_branch_arcs.end());

  const BlockId start_block = BlocksAroundHalfarc(mesh, first).front();
  for (int sector = 0; sector < static_cast<int>(sectors.size()); ++sector) {
    SeparationStartConfiguration config;
    config.entity = e;
    config.sector = sector;
    config.is_link = true;
    config.start_node = mesh.entity_node_from(e);
    config.start_block = start_block;
    config.link_dir = DirIn(mesh, first, start_block);
    config.cyclic_link = mesh.entity_node_from(e) == mesh.entity_node_to(e);
    configs_.push_back(config);
    branch_offs_.Append(sectors[sector]);
    pre_branch_arcs_.Append(pre_branch_arcs);
  }
}

}  // namespace ispq
