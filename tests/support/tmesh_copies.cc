// SPDX-License-Identifier: Apache-2.0
#include "tests/support/tmesh_copies.h"

#include <cstdint>

#include "absl/strings/str_cat.h"
#include "google/protobuf/repeated_field.h"

namespace ispq::testing {
namespace {

// Offsets of one copy's ids. Halfarc and halfpatch ids are 2 * id + side, so they shift by
// twice the element offset. -1 ("none") stays -1.
struct IdOffsets {
  int32_t node = 0;
  int32_t arc = 0;
  int32_t patch = 0;
  int32_t block = 0;
};

void Shift(google::protobuf::RepeatedField<int32_t>& ids, int32_t offset) {
  for (int32_t& id : ids) {
    if (id >= 0) id += offset;
  }
}

int32_t Shifted(int32_t id, int32_t offset) { return id >= 0 ? id + offset : id; }

void ShiftCopy(const IdOffsets& o, v1::TMesh& copy) {
  for (v1::Node& node : *copy.mutable_nodes()) Shift(*node.mutable_outgoing_halfarcs(), 2 * o.arc);
  for (v1::Arc& arc : *copy.mutable_arcs()) {
    arc.set_from(Shifted(arc.from(), o.node));
    arc.set_to(Shifted(arc.to(), o.node));
    Shift(*arc.mutable_halfpatches(), 2 * o.patch);
  }
  for (v1::Patch& patch : *copy.mutable_patches()) {
    Shift(*patch.mutable_blocks(), o.block);
    Shift(*patch.mutable_halfarcs(), 2 * o.arc);
    patch.set_ref_block(Shifted(patch.ref_block(), o.block));
    for (v1::DirectedHalfarcs& side : *patch.mutable_halfarcs_by_dir()) {
      Shift(*side.mutable_halfarcs(), 2 * o.arc);
    }
  }
  for (v1::Block& block : *copy.mutable_blocks()) {
    for (v1::Corner& corner : *block.mutable_corners()) {
      corner.set_node(Shifted(corner.node(), o.node));
    }
    for (v1::Edge& edge : *block.mutable_edges()) {
      Shift(*edge.mutable_arcs(), o.arc);
      Shift(*edge.mutable_halfarcs(), 2 * o.arc);
    }
    for (v1::Face& face : *block.mutable_faces()) {
      Shift(*face.mutable_patches(), o.patch);
      Shift(*face.mutable_arcs(), o.arc);
      Shift(*face.mutable_nodes(), o.node);
    }
    Shift(*block.mutable_halfpatches(), 2 * o.patch);
    for (v1::DirectedArcs& arcs : *block.mutable_arcs_by_dir()) Shift(*arcs.mutable_arcs(), o.arc);
    for (v1::NodeUvw& uvw : *block.mutable_node_uvw()) uvw.set_node(Shifted(uvw.node(), o.node));
  }
}

}  // namespace

v1::TMesh DisjointCopies(const v1::TMesh& mesh, int copies) {
  v1::TMesh result = mesh;
  result.set_name(absl::StrCat(mesh.name(), "x", copies));
  result.clear_levels();
  result.clear_stats();
  result.clear_nodes();
  result.clear_arcs();
  result.clear_patches();
  result.clear_blocks();
  result.clear_critical_entities();
  for (int k = 0; k < copies; ++k) {
    const IdOffsets offsets = {.node = k * mesh.nodes_size(),
                               .arc = k * mesh.arcs_size(),
                               .patch = k * mesh.patches_size(),
                               .block = k * mesh.blocks_size()};
    v1::TMesh copy = mesh;
    ShiftCopy(offsets, copy);
    for (v1::Node& node : *copy.mutable_nodes()) *result.add_nodes() = std::move(node);
    for (v1::Arc& arc : *copy.mutable_arcs()) *result.add_arcs() = std::move(arc);
    for (v1::Patch& patch : *copy.mutable_patches()) *result.add_patches() = std::move(patch);
    for (v1::Block& block : *copy.mutable_blocks()) *result.add_blocks() = std::move(block);
  }
  return result;
}

}  // namespace ispq::testing
