// SPDX-License-Identifier: Apache-2.0
// The lazy separation search for fixed singularities (core/README.md, section The lazy separation
// search; Brueckler, Bommes, Campen 2022, Alg. 1): from every critical node and critical link, a
// Dijkstra-like search for weakly monotone zero-length paths to another critical entity. Each hit
// yields a separation row in a default form (mixed axes as signed differences) and a failsafe form
// (non-negative coefficients only, paper App. B).
//
// The search is integer arithmetic on flat arrays. One instance keeps the tables that depend on
// the mesh alone (core/separation_search_tables.h, built as the searches read them) and its
// scratch buffers across calls, or shares both with another instance of the same mesh, so one
// instance serves one thread. A call computes block positions and patch boxes only for the blocks
// its fans reach.
//
// Why one file of ~700 lines: the walk, its heap order, the fan of candidate moves and the
// admissibility test share one set of invariants (core/README.md, section The lazy separation
// search) and one scratch state; the parts that stand alone are apart (mesh tables, start
// configurations, parallel classes, the bounds that prune walks in core/walk_slack.h,
// neighbourhoods of halfarcs, block node positions, integer boxes).
#ifndef ISPQ_CORE_SEPARATION_SEARCH_H_
#define ISPQ_CORE_SEPARATION_SEARCH_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "core/separation_row.h"
#include "core/tmesh.h"

namespace ispq {

// How a block's box is formed in the start frame (core/README.md, section Block admissibility and
// the two block-box modes). kSorted is the correct behaviour; kReferenceUnsorted reproduces the
// reference implementation, which rejects blocks reached through a sign-flipping rotation, for
// comparisons with upstream results.
enum class BlockBoxMode : uint8_t { kSorted, kReferenceUnsorted };

struct SeparationSearchOptions {
  BlockBoxMode block_box = BlockBoxMode::kSorted;
  // Skip the work that cannot report (core/README.md, section Hopeless walks): a walk is hopeless
  // by the negative lengths of its direction's parallel class, and a start whose every branch-off
  // is longer than those is settled without a walk. The answer is the same either way; tests that
  // compare turn it off, and then every start is walked and a walk is hopeless only by the
  // negative lengths of the whole mesh.
  bool prune_by_parallel_slack = true;
};

enum class SeparationTargetKind : uint8_t { kNode, kArc, kPatch };

// One violation: a zero-length weakly monotone path between two critical entities.
struct SeparationViolation {
  EntityId start_entity;  // a critical node or link (an id into the mesh's critical entities)
  int sector;             // index of the start configuration of that entity
  SeparationTargetKind target_kind;
  int32_t target;               // node, arc or patch id
  std::vector<HalfarcId> path;  // halfarcs walked after leaving the start entity
  SeparationRow default_row;    // coefficients in {-1, +1}, rhs 1
  SeparationRow failsafe_row;   // coefficients +1 only, rhs 1
  // Whether start_entity is a critical node or a link, and the node the search started from
  // (the critical node, or the link's first node), so that reports can name them.
  EntityDim start_dim = EntityDim::kNode;
  NodeId start_node = kNoId;
  BlockBoxMode found_by = BlockBoxMode::kSorted;  // the search that found it
};

class SeparationSearch {
 public:
  explicit SeparationSearch(const TMesh& mesh, SeparationSearchOptions options = {});
  // A search of the same mesh that shares the mesh tables and the per-call buffers of
  // `sharing_with` (which may be destroyed first) instead of building its own: half the memory
  // and half the construction when two searches run. Calls of the two must not overlap, which
  // one thread calling one of them at a time (never from a sink) guarantees.
  SeparationSearch(const TMesh& mesh, const SeparationSearch& sharing_with,
                   SeparationSearchOptions options);
  ~SeparationSearch();
  SeparationSearch(SeparationSearch&&) noexcept;
  SeparationSearch& operator=(SeparationSearch&&) noexcept;

  // Runs every start configuration (critical nodes by id, then links) on q, which must be
  // consistent; at most one violation per start configuration, in that order. Deterministic.
  // q.size() must be the mesh's number of arcs (a mismatch aborts: it is a caller bug). The
  // mesh must outlive this object.
  std::vector<SeparationViolation> FindViolations(std::span<const int64_t> q);
  // The same violations handed to `sink` one by one as they are found; the search stops when
  // the sink returns false. Returns how many were handed over.
  int64_t FindViolations(std::span<const int64_t> q,
                         const std::function<bool(SeparationViolation&)>& sink);

  // How many start configurations the calls so far did not run again because they came back
  // clean on an earlier call's q and nothing they read has changed since (core/clean_starts.h):
  // the violations reported are the same as a new instance's on the same q.
  int64_t skipped_starts() const;
  // How many start configurations the calls so far settled as clean from the lengths of their
  // branch-off arcs alone, without a walk (SeparationSearchOptions::prune_by_parallel_slack).
  int64_t settled_at_branch_offs() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_SEPARATION_SEARCH_H_
