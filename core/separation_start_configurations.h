// SPDX-License-Identifier: Apache-2.0
// The start configurations of the separation search (core/README.md, section Start configurations):
// one search per outgoing halfarc of every critical node, and one per halfpatch around the first
// halfarc of every critical link. Each fixes the start node, the start block whose frame is the
// search's reference frame, the halfarcs through which the search may leave the start entity
// (BranchOffs) and, for links, the arcs whose block choice is checked before branching (PreArcs).
// All of this depends on topology only, so it is built once per mesh.
#ifndef ISPQ_CORE_SEPARATION_START_CONFIGURATIONS_H_
#define ISPQ_CORE_SEPARATION_START_CONFIGURATIONS_H_

#include <span>
#include <vector>

#include "core/direction.h"
#include "core/flat_lists.h"
#include "core/tmesh.h"

namespace ispq {

struct SeparationStartConfiguration {
  EntityId entity;  // a critical node or link
  int sector;       // index among the configurations of that entity
  bool is_link;
  NodeId start_node;    // the critical node, or the link's first node
  BlockId start_block;  // b0: the lowest block at the node, or the first block around h_1
  // Link starts only: direction of the link's first halfarc in start_block's frame. The link
  // axis A1 is both senses of it; node starts have an empty A1.
  Dir link_dir = Dir::kPosU;
  bool cyclic_link = false;  // the link returns to its first node: unbounded along its axis
};

class SeparationStartConfigurations {
 public:
  explicit SeparationStartConfigurations(const TMesh& mesh);

  int size() const { return static_cast<int>(configs_.size()); }
  const SeparationStartConfiguration& operator[](int i) const { return configs_[i]; }

  // Halfarcs through which configuration i may leave its start entity: the sector's outgoing
  // halfarc for a node, the orthogonal halfarcs bounding the sector's wall for a link.
  std::span<const HalfarcId> branch_offs(int i) const { return branch_offs_[i]; }
  // Arcs that may be walked before branching only along the link axis (shared by all sectors of
  // a link, empty for node starts).
  std::span<const ArcId> pre_branch_arcs(int i) const { return pre_branch_arcs_[i]; }

  // The set of the link axis directions of configuration i (A1).
  DirSet link_axis(int i) const {
    return configs_[i].is_link ? AxisBits(AxisOf(configs_[i].link_dir)) : DirSet{0};
  }

 private:
  void AddNodeConfigurations(const TMesh& mesh, EntityId e);
  // `in_link` is all zero over the halfarcs on entry and on return (one array for all links:
  // a fresh one per link cost O(links * halfarcs)).
  void AddLinkConfigurations(const TMesh& mesh, EntityId e, std::vector<uint8_t>& in_link);

  std::vector<SeparationStartConfiguration> configs_;
  FlatLists<HalfarcId> branch_offs_;
  FlatLists<ArcId> pre_branch_arcs_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_SEPARATION_START_CONFIGURATIONS_H_
