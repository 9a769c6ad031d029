// SPDX-License-Identifier: Apache-2.0
#include "core/proto/tmesh_from_proto.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "absl/strings/str_join.h"
#include "core/critical_entities.h"
#include "core/direction.h"
#include "core/invalid_argument.h"
#include "core/proto/block_from_proto.h"
#include "core/proto/id_ranges.h"
#include "core/proto/repeated_field_span.h"
#include "core/rotation.h"
#include "core/status_macros.h"
#include "core/tmesh_input.h"

namespace ispq {
namespace {

absl::StatusOr<TMeshHeader> DecodeHeader(const v1::TMesh& proto, const TMeshSizes& sizes) {
  if (proto.format_version() != 1) {
    return InvalidArgument("formatVersion is ", proto.format_version(), ", only 1 is supported");
  }
  const v1::FeaturesPresent& present = proto.features_present();
  return TMeshHeader{.name = proto.name(),
                     .sizes = sizes,
                     .features_present = {present.nodes(), present.arcs(), present.patches()}};
}

absl::StatusOr<NodeInput> DecodeNode(NodeId n, const v1::Node& node, const IdRanges& ids) {
  if (node.position_size() != 3) {
    return InvalidArgument("node ", n, ": position has ", node.position_size(),
                           " coordinates, not 3");
  }
  for (double x : node.position()) {
    if (!std::isfinite(x)) return InvalidArgument("node ", n, ": position is not finite");
  }
  for (int32_t h : node.outgoing_halfarcs()) {
    if (!ids.Halfarc(h)) {
      return InvalidArgument("node ", n, ": outgoing halfarc ", h, " does not exist");
    }
  }
  if (!v1::SingularType::Value_IsValid(node.singular_type()) ||
      !v1::FeatureType::Value_IsValid(node.feature_type())) {
    return InvalidArgument("node ", n, ": unknown singularType or featureType");
  }
  return NodeInput{.outgoing_halfarcs = View(node.outgoing_halfarcs()),
                   .critical = node.critical(),
                   .feature = node.feature(),
                   .boundary = node.boundary(),
                   .singular_type = static_cast<SingularType>(node.singular_type()),
                   .feature_type = static_cast<FeatureType>(node.feature_type())};
}

absl::StatusOr<ArcInput> DecodeArc(ArcId a, const v1::Arc& arc, const IdRanges& ids) {
  if (!ids.Node(arc.from())) {
    return InvalidArgument("arc ", a, ": node 'from' ", arc.from(), " does not exist");
  }
  if (!ids.Node(arc.to())) {
    return InvalidArgument("arc ", a, ": node 'to' ", arc.to(), " does not exist");
  }
  for (int32_t hp : arc.halfpatches()) {
    if (!ids.Halfpatch(hp)) {
      return InvalidArgument("arc ", a, ": halfpatch ", hp, " does not exist");
    }
  }
  return ArcInput{.from = arc.from(),
                  .to = arc.to(),
                  .length = arc.length(),
                  .singular = arc.singular(),
                  .feature = arc.feature(),
                  .boundary = arc.boundary(),
                  .critical = arc.critical(),
                  .halfpatches = View(arc.halfpatches())};
}

// The block on each side and the face of it the patch lies on; NONE where there is no block.
absl::Status DecodePatchBlocks(PatchId p, const v1::Patch& patch, const IdRanges& ids,
                               PatchInput& input) {
  if (patch.blocks_size() != 2 || patch.sides_size() != 2) {
    return InvalidArgument("patch ", p, ": needs exactly 2 blocks and 2 sides");
  }
  for (int k = 0; k < 2; ++k) {
    const int32_t b = patch.blocks(k);
    input.blocks[k] = b;
    if (b == kNoId) {
      if (patch.sides(k) != v1::NONE) {
        return InvalidArgument("patch ", p, ": side ", k, " has no block but is not NONE");
      }
      continue;
    }
    if (!ids.Block(b)) return InvalidArgument("patch ", p, ": block ", b, " does not exist");
    const std::optional<Dir> side = DirFromUpstreamBits(patch.sides(k));
    if (!side) {
      return InvalidArgument("patch ", p, ": side ", k, " is not one of the 6 block face sides");
    }
    input.face_sides[k] = *side;
  }
  return absl::OkStatus();
}

absl::Status DecodeTransition(PatchId p, const v1::Transition& transition, PatchInput& input) {
  const auto& r = transition.rotation();
  if (r.size() != 3) return InvalidArgument("patch ", p, ": transition rotation needs 3 entries");
  const std::optional<Rotation> rotation = Rotation::FromSignedPermutation({r[0], r[1], r[2]});
  if (!rotation) {
    return InvalidArgument("patch ", p, ": transition rotation [", absl::StrJoin(r, ","),
                           "] is not a proper signed axis permutation");
  }
  if (transition.translation_size() != 0 && transition.translation_size() != 3) {
    return InvalidArgument("patch ", p, ": transition translation needs 3 entries");
  }
  for (double t : transition.translation()) {
    if (!std::isfinite(t)) {
      return InvalidArgument("patch ", p, ": transition translation is not finite");
    }
  }
  input.rotation = *rotation;
  return absl::OkStatus();
}

// The cycle's halfarcs, and the four sides with their directions.
absl::Status DecodeCycleAndSides(PatchId p, const v1::Patch& patch, const IdRanges& ids,
                                 PatchInput& input) {
  for (int32_t h : patch.halfarcs()) {
    if (!ids.Halfarc(h)) return InvalidArgument("patch ", p, ": halfarc ", h, " does not exist");
  }
  input.cycle = View(patch.halfarcs());
  if (patch.halfarcs_by_dir_size() != 4) {
    return InvalidArgument("patch ", p, ": has ", patch.halfarcs_by_dir_size(), " sides, not 4");
  }
  for (int i = 0; i < 4; ++i) {
    const v1::DirectedHalfarcs& side = patch.halfarcs_by_dir(i);
    const std::optional<Dir> dir = DirFromUpstreamBits(side.dir());
    if (!dir) return InvalidArgument("patch ", p, ": side ", i, " has no single direction");
    input.sides[i] = {*dir, View(side.halfarcs())};
  }
  return absl::OkStatus();
}

absl::StatusOr<PatchInput> DecodePatch(PatchId p, const v1::Patch& patch, const IdRanges& ids) {
  PatchInput input;
  ISPQ_RETURN_IF_ERROR(DecodePatchBlocks(p, patch, ids, input));
  ISPQ_RETURN_IF_ERROR(DecodeTransition(p, patch.transition(), input));
  ISPQ_RETURN_IF_ERROR(DecodeCycleAndSides(p, patch, ids, input));
  input.feature = patch.feature();
  input.boundary = patch.boundary();
  input.critical = patch.critical();
  input.ref_block = patch.ref_block();
  return input;
}

// Decodes each element the source hands over and adds it to the builder, keeping of each patch
// the transition translation that CheckTranslations needs once the mesh is built.
class ElementDecoder final : public TMeshElementSink {
 public:
  ElementDecoder(const TMeshSizes& sizes, TMeshBuilder& builder) : ids_(sizes), builder_(builder) {}

  absl::Status Node(const v1::Node& node) override {
    ISPQ_ASSIGN_OR_RETURN(const NodeInput input, DecodeNode(nodes_++, node, ids_));
    return builder_.AddNode(input);
  }
  absl::Status Arc(const v1::Arc& arc) override {
    ISPQ_ASSIGN_OR_RETURN(const ArcInput input, DecodeArc(arcs_++, arc, ids_));
    return builder_.AddArc(input);
  }
  absl::Status Patch(const v1::Patch& patch) override {
    ISPQ_ASSIGN_OR_RETURN(const PatchInput input, DecodePatch(patches_++, patch, ids_));
    const auto& t = patch.transition().translation();
    translations_.push_back(t.size() == 3 ? std::optional<std::array<double, 3>>({t[0], t[1], t[2]})
                                          : std::nullopt);
    return builder_.AddPatch(input);
  }
  absl::Status Block(const v1::Block& block) override {
    ISPQ_ASSIGN_OR_RETURN(BlockInput input, BlockInputFromProto(blocks_++, block, ids_));
    return builder_.AddBlock(std::move(input));
  }

  bool HasAll(const TMeshSizes& sizes) const {
    return nodes_ == sizes.nodes && arcs_ == sizes.arcs && patches_ == sizes.patches &&
           blocks_ == sizes.blocks;
  }
  // Per patch: its transition's translation, if the file gave one.
  std::vector<std::optional<std::array<double, 3>>>& translations() { return translations_; }

 private:
  const IdRanges ids_;
  TMeshBuilder& builder_;
  int32_t nodes_ = 0, arcs_ = 0, patches_ = 0, blocks_ = 0;
  std::vector<std::optional<std::array<double, 3>>> translations_;
};

// The entity list a request may send; its ids must be its positions. The builder compares it
// with the entities the mesh makes, which need not be range-checked: they are never indexed.
absl::StatusOr<std::vector<CriticalEntity>> DecodeCriticalEntities(const v1::TMesh& proto) {
  std::vector<CriticalEntity> entities;
  for (int e = 0; e < proto.critical_entities_size(); ++e) {
    const v1::CriticalEntity& entity = proto.critical_entities(e);
    if (entity.id() != e) return InvalidArgument("critical entity ", e, ": id is ", entity.id());
    if (entity.dim() < 0 || entity.dim() > 2) {
      return InvalidArgument("critical entity ", e, ": dim ", entity.dim(), " is not 0, 1 or 2");
    }
    CriticalEntity& decoded = entities.emplace_back();
    decoded.dim = static_cast<EntityDim>(entity.dim());
    if (decoded.dim != EntityDim::kRegion) {
      decoded.node_from = entity.node_from();
      decoded.node_to = entity.node_to();
    }
    decoded.halfarcs.assign(entity.halfarcs().begin(), entity.halfarcs().end());
    decoded.patches.assign(entity.patches().begin(), entity.patches().end());
    decoded.boundary_arcs.assign(entity.boundary_arcs().begin(), entity.boundary_arcs().end());
  }
  return entities;
}

const std::array<double, 3>* FindUvw(const TMesh& mesh, BlockId b, NodeId n) {
  const auto list = mesh.block_node_uvw(b);
  const auto it = std::lower_bound(list.begin(), list.end(), n,
                                   [](const BlockNodeUvw& e, NodeId id) { return e.node < id; });
  return it != list.end() && it->node == n ? &it->uvw : nullptr;
}

// Each interior patch's transition T(x) = R x + t, where t is given, carries every node of its
// cycle from its coordinates in the first block's frame to those in the second's. The model keeps
// only R (the algorithms never need t), so this is the decoder's to check, on the built mesh: there
// every cycle arc is known to lie on both blocks, with coordinates for both of its nodes. The
// tolerance is the builder's for coordinates, relative to the largest coordinate involved (at
// least 1). The format lets t be omitted (proto/README.md, section Transitions): then there is
// nothing to check it against, and compact files (the benchmark's largest meshes) leave it out.
absl::Status CheckTranslations(std::span<const std::optional<std::array<double, 3>>> translations,
                               const TMesh& mesh, double tolerance) {
  for (PatchId p = 0; p < mesh.num_patches(); ++p) {
    const BlockId b0 = mesh.patch_block(p, 0), b1 = mesh.patch_block(p, 1);
    if (b0 == kNoId || b1 == kNoId) continue;
    if (!translations[p].has_value()) continue;  // omitted (0 or 3 entries, DecodeTransition)
    const std::array<double, 3>& t = *translations[p];
    for (HalfarcId h : mesh.patch_cycle(p)) {
      const NodeId n = mesh.tail(h);
      const std::array<double, 3>* from = FindUvw(mesh, b0, n);
      const std::array<double, 3>* to = FindUvw(mesh, b1, n);
      if (!from || !to) {
        return InvalidArgument("patch ", p, ": node ", n, " has no coordinates in block ",
                               from ? b1 : b0);
      }
      std::array<double, 3> image = mesh.patch_rotation(p).Apply(*from);
      double scale = 1.0;
      for (int i = 0; i < 3; ++i) {
        image[i] += t[i];
        scale = std::max({scale, std::abs(image[i]), std::abs((*to)[i])});
      }
      for (int i = 0; i < 3; ++i) {
        if (std::abs(image[i] - (*to)[i]) > tolerance * scale) {
          return InvalidArgument("patch ", p, ": transition translation [", absl::StrJoin(t, ","),
                                 "] does not carry node ", n, " from its coordinates in block ", b0,
                                 " to those in block ", b1);
        }
      }
    }
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<TMesh> TMeshFromParts(const v1::TMesh& header_fields, const TMeshSizes& sizes,
                                     const TMeshElementSource& elements,
                                     const TMeshValidationOptions& options) {
  ISPQ_ASSIGN_OR_RETURN(const TMeshHeader header, DecodeHeader(header_fields, sizes));
  ISPQ_ASSIGN_OR_RETURN(TMeshBuilder builder, TMeshBuilder::Create(header, options));
  ElementDecoder decoder(sizes, builder);
  ISPQ_RETURN_IF_ERROR(elements(decoder));
  if (!decoder.HasAll(sizes)) {
    return InvalidArgument("the mesh's element lists changed while it was read");
  }
  ISPQ_RETURN_IF_ERROR(builder.Connect());
  ISPQ_ASSIGN_OR_RETURN(const std::vector<CriticalEntity> listed,
                        DecodeCriticalEntities(header_fields));
  ISPQ_RETURN_IF_ERROR(builder.DeriveCriticalEntities(listed));
  for (const v1::Level& level : header_fields.levels()) {
    ISPQ_RETURN_IF_ERROR(builder.AddLevel({level.percent(), level.scaling()}));
  }
  ISPQ_ASSIGN_OR_RETURN(TMesh mesh, std::move(builder).Build());
  ISPQ_RETURN_IF_ERROR(CheckTranslations(decoder.translations(), mesh, options.length_tolerance));
  return mesh;
}

absl::StatusOr<TMesh> TMeshFromProto(const v1::TMesh& proto,
                                     const TMeshValidationOptions& options) {
  const TMeshSizes sizes{proto.nodes_size(), proto.arcs_size(), proto.patches_size(),
                         proto.blocks_size()};
  return TMeshFromParts(
      proto, sizes,
      [&proto](TMeshElementSink& sink) -> absl::Status {
        for (const v1::Node& node : proto.nodes()) ISPQ_RETURN_IF_ERROR(sink.Node(node));
        for (const v1::Arc& arc : proto.arcs()) ISPQ_RETURN_IF_ERROR(sink.Arc(arc));
        for (const v1::Patch& patch : proto.patches()) ISPQ_RETURN_IF_ERROR(sink.Patch(patch));
        for (const v1::Block& block : proto.blocks()) ISPQ_RETURN_IF_ERROR(sink.Block(block));
        return absl::OkStatus();
      },
      options);
}

}  // namespace ispq
