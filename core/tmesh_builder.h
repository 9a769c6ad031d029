// SPDX-License-Identifier: Apache-2.0
// Builds the immutable TMesh (core/tmesh.h) from plain element data (core/tmesh_input.h), checking
// the rules of proto/README.md (section What the loader checks, steps 2 to 8) and deriving the
// adjacency the model precomputes. It is the only code that writes a TMesh, so a TMesh that exists
// has passed every check; it knows no file format (core/proto/tmesh_from_proto.h decodes the
// ispq.v1 message into its input).
//
// The build runs in a fixed order, each step reading only what earlier steps checked:
//
//   ISPQ_ASSIGN_OR_RETURN(TMeshBuilder builder, TMeshBuilder::Create(header));
//   builder.AddNode(...) for every node in id order, then AddArc, AddPatch, AddBlock likewise;
//   builder.Connect();                          // incidences, frames, adjacency, criticality
//   builder.DeriveCriticalEntities(listed);     // listed may be empty
//   builder.AddLevel(...) for every level;      // optional
//   ISPQ_ASSIGN_OR_RETURN(TMesh mesh, std::move(builder).Build());
//
// Each element is checked against its own rules when added (core/tmesh_element_checks.h,
// core/tmesh_patch_checks.h), so the first broken element in id order is reported; the rules
// between elements run in Connect (core/tmesh_incidence_checks.h, core/tmesh_frame_checks.h,
// core/tmesh_criticality_checks.h). A broken rule is INVALID_ARGUMENT naming the element; a
// call out of this order is FAILED_PRECONDITION. After any error the builder is done with.
#ifndef ISPQ_CORE_TMESH_BUILDER_H_
#define ISPQ_CORE_TMESH_BUILDER_H_

#include <cstdint>
#include <span>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "core/critical_entities.h"
#include "core/flat_lists.h"
#include "core/tmesh.h"
#include "core/tmesh_criticality_checks.h"
#include "core/tmesh_input.h"

namespace ispq {

struct TMeshValidationOptions {
  // Relative tolerance for continuous-length identities: opposite patch sides, and
  // uvw(to) - uvw(from) = length * dir for every arc of a block.
  double length_tolerance = 1e-6;
};

class TMeshBuilder {
 public:
  // INVALID_ARGUMENT if a kind has no elements or too many for int32 halfarc/halfpatch ids.
  static absl::StatusOr<TMeshBuilder> Create(const TMeshHeader& header,
                                             const TMeshValidationOptions& options = {});

  TMeshBuilder(TMeshBuilder&&) = default;
  TMeshBuilder& operator=(TMeshBuilder&&) = default;

  absl::Status AddNode(const NodeInput& node);
  absl::Status AddArc(const ArcInput& arc);
  absl::Status AddPatch(const PatchInput& patch);
  absl::Status AddBlock(BlockInput block);

  // Checks how the elements fit together and derives node and arc adjacency.
  absl::Status Connect();

  // Derives the critical entities; a non-empty `listed` (a request's list) must equal them.
  absl::Status DeriveCriticalEntities(std::span<const CriticalEntity> listed);

  absl::Status AddLevel(const Level& level);

  absl::StatusOr<TMesh> Build() &&;

 private:
  enum class Stage : uint8_t { kNodes, kArcs, kPatches, kBlocks, kConnect, kEntities, kLevels };

  TMeshBuilder(const TMeshHeader& header, const TMeshValidationOptions& options);

  void SizeArrays();
  absl::Status Expect(Stage stage) const;
  // Ends the stage once `added` elements of its kind are in, out of `size`.
  void Advance(int added, int size);
  void DeriveNodeAdjacency();
  void DeriveArcBlocks();

  TMeshSizes sizes_;
  FeaturesPresent features_;
  TMeshValidationOptions options_;
  Stage stage_ = Stage::kNodes;
  int next_ = 0;  // id of the next element of the stage's kind
  TMesh mesh_;
  // For CheckBlockEdgeChains: per block, the 12 edges' halfarcs by edge code, and the codes in
  // the order the input listed them.
  FlatLists<HalfarcId> edge_halfarcs_;
  std::vector<int8_t> edge_order_;
  // For CheckNodeTypes: each node's stated types, which the model does not keep.
  std::vector<NodeTypes> node_types_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_TMESH_BUILDER_H_
