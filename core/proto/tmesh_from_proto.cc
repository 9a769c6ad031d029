#include "core/proto/tmesh_from_proto.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/arc_singularity.h"
#include "core/critical_entities.h"
#include "core/resolution_levels.h"

namespace ispq {

// Builds a TMesh from a message, checking each rule before the data it guards is used. The
// checks run in dependency order: ids are range-checked before anything is indexed by them, and
// derived adjacency is built only from checked data.
class TMeshAssembler {
 public:
  TMeshAssembler(const v1::TMesh& proto, const TMeshValidationOptions& options)
      : proto_(proto), options_(options) {}

  absl::StatusOr<TMesh> Assemble() {
    for (absl::Status (TMeshAssembler::*step)() :
         {&TMeshAssembler::CheckTopLevel, &TMeshAssembler::LoadNodes, &TMeshAssembler::LoadArcs,
          &TMeshAssembler::LoadPatches, &TMeshAssembler::LoadBlocks,
          &TMeshAssembler::CheckNodeArcIncidence, &TMeshAssembler::CheckArcPatchIncidence,
          &TMeshAssembler::CheckPatchBlockIncidence, &TMeshAssembler::CheckPatchGeometry,
          &TMeshAssembler::CheckBlockEdges, &TMeshAssembler::CheckBlockCoordinates,
          &TMeshAssembler::DeriveAdjacency, &TMeshAssembler::CheckArcSingularity,
          &TMeshAssembler::CheckCriticalNodes, &TMeshAssembler::DeriveCriticalEntities,
          &TMeshAssembler::LoadLevels}) {
      if (absl::Status status = (this->*step)(); !status.ok()) return status;
    }
    return std::move(mesh_);
  }

 private:
  template <typename... Args>
  static absl::Status Invalid(const Args&... args) {
    return absl::InvalidArgumentError(absl::StrCat(args...));
  }

  bool ValidNode(int64_t n) const { return n >= 0 && n < num_nodes_; }
  bool ValidArc(int64_t a) const { return a >= 0 && a < num_arcs_; }
  bool ValidHalfarc(int64_t h) const { return h >= 0 && h < 2 * static_cast<int64_t>(num_arcs_); }
  bool ValidPatch(int64_t p) const { return p >= 0 && p < num_patches_; }
  bool ValidHalfpatch(int64_t hp) const {
    return hp >= 0 && hp < 2 * static_cast<int64_t>(num_patches_);
  }
  bool ValidBlock(int64_t b) const { return b >= 0 && b < num_blocks_; }

  absl::Status CheckTopLevel() {
    if (proto_.format_version() != 1) {
      return Invalid("formatVersion is ", proto_.format_version(), ", only 1 is supported");
    }
    // Counts are bounded by the message itself; halfarc and halfpatch ids must fit in int32.
    constexpr int kMaxElements = std::numeric_limits<int32_t>::max() / 2;
    const std::pair<const char*, int> counts[] = {{"nodes", proto_.nodes_size()},
                                                  {"arcs", proto_.arcs_size()},
                                                  {"patches", proto_.patches_size()},
                                                  {"blocks", proto_.blocks_size()}};
    for (const auto& [what, count] : counts) {
      if (count == 0) return Invalid("the mesh has no ", what);
      if (count > kMaxElements) return Invalid("the mesh has too many ", what, ": ", count);
    }
    num_nodes_ = proto_.nodes_size();
    num_arcs_ = proto_.arcs_size();
    num_patches_ = proto_.patches_size();
    num_blocks_ = proto_.blocks_size();
    mesh_.name_ = proto_.name();
    const v1::FeaturesPresent& fp = proto_.features_present();
    mesh_.features_present_ = fp.nodes() || fp.arcs() || fp.patches();
    return absl::OkStatus();
  }

  absl::Status LoadNodes() {
    mesh_.node_critical_.resize(num_nodes_);
    mesh_.node_feature_.resize(num_nodes_);
    mesh_.node_boundary_.resize(num_nodes_);
    mesh_.node_singular_type_.resize(num_nodes_);
    mesh_.node_feature_type_.resize(num_nodes_);
    for (int n = 0; n < num_nodes_; ++n) {
      const v1::Node& node = proto_.nodes(n);
      if (node.position_size() != 3) {
        return Invalid("node ", n, ": position has ", node.position_size(), " coordinates, not 3");
      }
      for (double x : node.position()) {
        if (!std::isfinite(x)) return Invalid("node ", n, ": position is not finite");
      }
      for (int32_t h : node.outgoing_halfarcs()) {
        if (!ValidHalfarc(h))
          return Invalid("node ", n, ": outgoing halfarc ", h, " does not exist");
      }
      if (!v1::SingularType::Value_IsValid(node.singular_type()) ||
          !v1::FeatureType::Value_IsValid(node.feature_type())) {
        return Invalid("node ", n, ": unknown singularType or featureType");
      }
      if (node.feature() && !proto_.features_present().nodes()) {
        return Invalid("node ", n, ": marked feature but featuresPresent.nodes is false");
      }
      mesh_.node_outgoing_.Append(node.outgoing_halfarcs());
      mesh_.node_critical_[n] = node.critical();
      mesh_.node_feature_[n] = node.feature();
      mesh_.node_boundary_[n] = node.boundary();
      mesh_.node_singular_type_[n] = static_cast<SingularType>(node.singular_type());
      mesh_.node_feature_type_[n] = static_cast<FeatureType>(node.feature_type());
    }
    return absl::OkStatus();
  }

  absl::Status LoadArcs() {
    mesh_.arc_from_.resize(num_arcs_);
    mesh_.arc_to_.resize(num_arcs_);
    mesh_.arc_length_.resize(num_arcs_);
    mesh_.arc_singular_.resize(num_arcs_);
    mesh_.arc_feature_.resize(num_arcs_);
    mesh_.arc_boundary_.resize(num_arcs_);
    mesh_.arc_critical_.resize(num_arcs_);
    for (int a = 0; a < num_arcs_; ++a) {
      const v1::Arc& arc = proto_.arcs(a);
      if (!ValidNode(arc.from()))
        return Invalid("arc ", a, ": node 'from' ", arc.from(), " does not exist");
      if (!ValidNode(arc.to()))
        return Invalid("arc ", a, ": node 'to' ", arc.to(), " does not exist");
      if (arc.from() == arc.to()) return Invalid("arc ", a, ": starts and ends at node ", arc.to());
      if (!std::isfinite(arc.length()) || arc.length() <= 0) {
        return Invalid("arc ", a, ": length ", arc.length(), " is not a positive finite number");
      }
      if (arc.singular() < -4 || arc.singular() > 4) {
        return Invalid("arc ", a, ": singular mark ", arc.singular(), " is out of range -4..4");
      }
      if (arc.critical() != (arc.singular() != 0 || arc.feature())) {
        return Invalid("arc ", a, ": critical flag ", arc.critical(),
                       " contradicts singular != 0 || feature");
      }
      if (arc.feature() && !proto_.features_present().arcs()) {
        return Invalid("arc ", a, ": marked feature but featuresPresent.arcs is false");
      }
      for (int32_t hp : arc.halfpatches()) {
        if (!ValidHalfpatch(hp)) return Invalid("arc ", a, ": halfpatch ", hp, " does not exist");
      }
      if (arc.halfpatches_size() == 0) return Invalid("arc ", a, ": lies on no patch");
      mesh_.arc_from_[a] = arc.from();
      mesh_.arc_to_[a] = arc.to();
      mesh_.arc_length_[a] = arc.length();
      mesh_.arc_singular_[a] = static_cast<int8_t>(arc.singular());
      mesh_.arc_feature_[a] = arc.feature();
      mesh_.arc_boundary_[a] = arc.boundary();
      mesh_.arc_critical_[a] = arc.critical();
      mesh_.arc_halfpatches_.Append(arc.halfpatches());
    }
    return absl::OkStatus();
  }

  static std::optional<Dir> SingleDir(v1::UVWDir d) { return DirFromUpstreamBits(d); }

  absl::Status LoadPatches() {
    mesh_.patch_blocks_.resize(num_patches_);
    mesh_.patch_face_sides_.resize(num_patches_);
    mesh_.patch_rotation_.resize(num_patches_);
    mesh_.patch_feature_.resize(num_patches_);
    mesh_.patch_boundary_.resize(num_patches_);
    mesh_.patch_critical_.resize(num_patches_);
    mesh_.patch_ref_block_.resize(num_patches_);
    mesh_.patch_side_dir_.resize(num_patches_);
    for (int p = 0; p < num_patches_; ++p) {
      if (absl::Status s = LoadPatch(p); !s.ok()) return s;
    }
    return absl::OkStatus();
  }

  absl::Status LoadPatch(int p) {
    const v1::Patch& patch = proto_.patches(p);
    if (patch.blocks_size() != 2 || patch.sides_size() != 2) {
      return Invalid("patch ", p, ": needs exactly 2 blocks and 2 sides");
    }
    int boundary_sides = 0;
    for (int k = 0; k < 2; ++k) {
      const int32_t b = patch.blocks(k);
      if (b == kNoId) {
        ++boundary_sides;
        if (patch.sides(k) != v1::NONE)
          return Invalid("patch ", p, ": side ", k, " has no block but is not NONE");
        mesh_.patch_face_sides_[p][k] = Dir::kPosU;
      } else {
        if (!ValidBlock(b)) return Invalid("patch ", p, ": block ", b, " does not exist");
        const std::optional<Dir> side = SingleDir(patch.sides(k));
        if (!side)
          return Invalid("patch ", p, ": side ", k, " is not one of the 6 block face sides");
        mesh_.patch_face_sides_[p][k] = *side;
      }
      mesh_.patch_blocks_[p][k] = b;
    }
    if (boundary_sides == 2) return Invalid("patch ", p, ": has no block on either side");
    if (patch.blocks(0) == patch.blocks(1)) {
      return Invalid("patch ", p, ": block ", patch.blocks(0),
                     " is on both sides (self-adjacent blocks are not supported)");
    }
    if (patch.boundary() != (boundary_sides == 1)) {
      return Invalid("patch ", p, ": boundary flag ", patch.boundary(), " contradicts its blocks");
    }
    if (patch.feature() && !proto_.features_present().patches()) {
      return Invalid("patch ", p, ": marked feature but featuresPresent.patches is false");
    }
    if (patch.critical() != (patch.boundary() || patch.feature())) {
      return Invalid("patch ", p, ": critical flag contradicts boundary || feature");
    }
    const v1::Transition& tr = patch.transition();
    if (tr.rotation_size() != 3)
      return Invalid("patch ", p, ": transition rotation needs 3 entries");
    const std::optional<Rotation> rotation =
        Rotation::FromSignedPermutation({tr.rotation(0), tr.rotation(1), tr.rotation(2)});
    if (!rotation) {
      return Invalid("patch ", p, ": transition rotation [", absl::StrJoin(tr.rotation(), ","),
                     "] is not a proper signed axis permutation");
    }
    if (boundary_sides == 1 && !rotation->IsIdentity()) {
      return Invalid("patch ", p, ": boundary patch with a non-identity transition");
    }
    if (tr.translation_size() != 0 && tr.translation_size() != 3) {
      return Invalid("patch ", p, ": transition translation needs 3 entries");
    }
    for (double t : tr.translation()) {
      if (!std::isfinite(t)) return Invalid("patch ", p, ": transition translation is not finite");
    }
    mesh_.patch_rotation_[p] = *rotation;
    mesh_.patch_feature_[p] = patch.feature();
    mesh_.patch_boundary_[p] = patch.boundary();
    mesh_.patch_critical_[p] = patch.critical();

    // The cycle: a closed chain of distinct arcs.
    const int size = patch.halfarcs_size();
    if (size < 4) return Invalid("patch ", p, ": cycle has ", size, " halfarcs, at least 4 needed");
    for (int i = 0; i < size; ++i) {
      if (!ValidHalfarc(patch.halfarcs(i))) {
        return Invalid("patch ", p, ": halfarc ", patch.halfarcs(i), " does not exist");
      }
    }
    std::vector<ArcId> arcs;
    for (int i = 0; i < size; ++i) {
      const HalfarcId h = patch.halfarcs(i);
      const HalfarcId next = patch.halfarcs((i + 1) % size);
      if (mesh_.head(h) != mesh_.tail(next)) {
        return Invalid("patch ", p, ": cycle is not closed: halfarc ", h, " ends at node ",
                       mesh_.head(h), " but halfarc ", next, " starts at node ", mesh_.tail(next));
      }
      arcs.push_back(ArcOf(h));
    }
    std::sort(arcs.begin(), arcs.end());
    if (std::adjacent_find(arcs.begin(), arcs.end()) != arcs.end()) {
      return Invalid("patch ", p, ": cycle uses an arc twice");
    }
    mesh_.patch_cycle_.Append(patch.halfarcs());

    const BlockId expected_ref = patch.blocks(0) != kNoId ? patch.blocks(0) : patch.blocks(1);
    if (patch.ref_block() != expected_ref) {
      return Invalid("patch ", p, ": refBlock ", patch.ref_block(), " should be ", expected_ref);
    }
    mesh_.patch_ref_block_[p] = expected_ref;

    // Four sides, two opposite pairs, that partition the cycle into contiguous runs.
    if (patch.halfarcs_by_dir_size() != 4) {
      return Invalid("patch ", p, ": has ", patch.halfarcs_by_dir_size(), " sides, not 4");
    }
    DirSet dirs = 0;
    for (int i = 0; i < 4; ++i) {
      const v1::DirectedHalfarcs& side = patch.halfarcs_by_dir(i);
      const std::optional<Dir> dir = SingleDir(side.dir());
      if (!dir) return Invalid("patch ", p, ": side ", i, " has no single direction");
      if (dirs & DirBit(*dir))
        return Invalid("patch ", p, ": direction ", DirName(*dir), " used by two sides");
      dirs |= DirBit(*dir);
      if (side.halfarcs_size() == 0)
        return Invalid("patch ", p, ": side ", DirName(*dir), " is empty");
      // The run must be contiguous in the cycle.
      const auto cycle = patch.halfarcs();
      const auto start = std::find(cycle.begin(), cycle.end(), side.halfarcs(0));
      if (start == cycle.end()) {
        return Invalid("patch ", p, ": side ", DirName(*dir), " halfarc ", side.halfarcs(0),
                       " is not in the cycle");
      }
      const int offset = static_cast<int>(start - cycle.begin());
      for (int j = 0; j < side.halfarcs_size(); ++j) {
        if (side.halfarcs_size() > size || cycle[(offset + j) % size] != side.halfarcs(j)) {
          return Invalid("patch ", p, ": side ", DirName(*dir),
                         " is not a contiguous run of the cycle");
        }
      }
      mesh_.patch_side_dir_[p][i] = *dir;
      mesh_.patch_side_halfarcs_.Append(side.halfarcs());
    }
    int total = 0;
    for (int i = 0; i < 4; ++i) total += patch.halfarcs_by_dir(i).halfarcs_size();
    if (total != size) return Invalid("patch ", p, ": sides do not partition the cycle");
    for (int axis = 0; axis < 3; ++axis) {
      const DirSet on_axis = dirs & AxisBits(axis);
      if (on_axis != 0 && on_axis != AxisBits(axis)) {
        return Invalid("patch ", p, ": sides are not two pairs of opposite directions");
      }
    }
    // Opposite sides have equal continuous length.
    for (int i = 0; i < 4; ++i) {
      const PatchSide side = mesh_.patch_side(p, i);
      if (IsNegative(side.dir)) continue;
      for (int j = 0; j < 4; ++j) {
        const PatchSide opposite = mesh_.patch_side(p, j);
        if (opposite.dir != Opposite(side.dir)) continue;
        const double a = SideLength(side.halfarcs), b = SideLength(opposite.halfarcs);
        if (std::abs(a - b) > options_.length_tolerance * std::max({1.0, a, b})) {
          return Invalid("patch ", p, ": side ", DirName(side.dir), " has continuous length ", a,
                         " but the opposite side ", DirName(opposite.dir), " has ", b);
        }
      }
    }
    return absl::OkStatus();
  }

  double SideLength(std::span<const HalfarcId> halfarcs) const {
    double sum = 0;
    for (HalfarcId h : halfarcs) sum += mesh_.arc_length_[ArcOf(h)];
    return sum;
  }

  absl::Status LoadBlocks() {
    mesh_.block_corners_.resize(num_blocks_);
    for (int b = 0; b < num_blocks_; ++b) {
      if (absl::Status s = LoadBlock(b); !s.ok()) return s;
    }
    return absl::OkStatus();
  }

  absl::Status LoadBlock(int b) {
    const v1::Block& block = proto_.blocks(b);
    if (block.self_adjacent())
      return Invalid("block ", b, ": self-adjacent blocks are not supported");
    if (block.corners_size() != kNumCorners) {
      return Invalid("block ", b, ": has ", block.corners_size(), " corners, not 8");
    }
    std::array<bool, kNumCorners> seen_corner{};
    for (const v1::Corner& c : block.corners()) {
      const std::optional<int> code = CornerFromUpstreamBits(c.corner());
      if (!code)
        return Invalid("block ", b, ": corner key ", v1::UVWDir_Name(c.corner()),
                       " is not a corner");
      if (seen_corner[*code])
        return Invalid("block ", b, ": corner ", v1::UVWDir_Name(c.corner()), " appears twice");
      if (!ValidNode(c.node()))
        return Invalid("block ", b, ": corner node ", c.node(), " does not exist");
      seen_corner[*code] = true;
      mesh_.block_corners_[b][*code] = c.node();
    }
    if (block.edges_size() != kNumEdges) {
      return Invalid("block ", b, ": has ", block.edges_size(), " edges, not 12");
    }
    std::array<const v1::Edge*, kNumEdges> edges{};
    for (const v1::Edge& e : block.edges()) {
      const std::optional<int> code = EdgeFromUpstreamBits(e.edge());
      if (!code)
        return Invalid("block ", b, ": edge key ", v1::UVWDir_Name(e.edge()), " is not an edge");
      if (edges[*code])
        return Invalid("block ", b, ": edge ", v1::UVWDir_Name(e.edge()), " appears twice");
      if (e.arcs_size() == 0)
        return Invalid("block ", b, ": edge ", v1::UVWDir_Name(e.edge()), " has no arcs");
      if (e.halfarcs_size() != e.arcs_size()) {
        return Invalid("block ", b, ": edge ", v1::UVWDir_Name(e.edge()), " lists ", e.arcs_size(),
                       " arcs but ", e.halfarcs_size(), " halfarcs");
      }
      for (int i = 0; i < e.arcs_size(); ++i) {
        if (!ValidArc(e.arcs(i)) || !ValidHalfarc(e.halfarcs(i)) ||
            ArcOf(e.halfarcs(i)) != e.arcs(i)) {
          return Invalid("block ", b, ": edge ", v1::UVWDir_Name(e.edge()), " arc ", e.arcs(i),
                         " / halfarc ", e.halfarcs(i), " is invalid");
        }
      }
      edges[*code] = &e;
    }
    for (int code = 0; code < kNumEdges; ++code) mesh_.block_edge_arcs_.Append(edges[code]->arcs());

    if (block.faces_size() != kNumDirs) {
      return Invalid("block ", b, ": has ", block.faces_size(), " faces, not 6");
    }
    std::array<const v1::Face*, kNumDirs> faces{};
    for (const v1::Face& f : block.faces()) {
      const std::optional<Dir> side = SingleDir(f.side());
      if (!side)
        return Invalid("block ", b, ": face key ", v1::UVWDir_Name(f.side()),
                       " is not a face side");
      if (faces[DirIndex(*side)])
        return Invalid("block ", b, ": face ", DirName(*side), " appears twice");
      if (f.patches_size() == 0)
        return Invalid("block ", b, ": face ", DirName(*side), " has no patches");
      for (int32_t p : f.patches()) {
        if (!ValidPatch(p))
          return Invalid("block ", b, ": face ", DirName(*side), " patch ", p, " does not exist");
      }
      for (int32_t a : f.arcs()) {
        if (!ValidArc(a))
          return Invalid("block ", b, ": face ", DirName(*side), " arc ", a, " does not exist");
      }
      for (int32_t n : f.nodes()) {
        if (!ValidNode(n))
          return Invalid("block ", b, ": face ", DirName(*side), " node ", n, " does not exist");
      }
      faces[DirIndex(*side)] = &f;
    }
    for (Dir d : kAllDirs) mesh_.block_face_patches_.Append(faces[DirIndex(d)]->patches());

    for (int32_t hp : block.halfpatches()) {
      if (!ValidHalfpatch(hp)) return Invalid("block ", b, ": halfpatch ", hp, " does not exist");
    }
    mesh_.block_halfpatches_.Append(block.halfpatches());

    std::vector<BlockArc> arcs;
    DirSet dirs_seen = 0;
    for (const v1::DirectedArcs& entry : block.arcs_by_dir()) {
      const std::optional<Dir> dir = SingleDir(entry.dir());
      if (!dir)
        return Invalid("block ", b, ": arcsByDir key ", v1::UVWDir_Name(entry.dir()),
                       " is not a direction");
      if (dirs_seen & DirBit(*dir))
        return Invalid("block ", b, ": arcsByDir lists ", DirName(*dir), " twice");
      dirs_seen |= DirBit(*dir);
      for (int32_t a : entry.arcs()) {
        if (!ValidArc(a)) return Invalid("block ", b, ": arcsByDir arc ", a, " does not exist");
        arcs.push_back({a, *dir});
      }
    }
    std::sort(arcs.begin(), arcs.end(),
              [](const BlockArc& x, const BlockArc& y) { return x.arc < y.arc; });
    for (size_t i = 1; i < arcs.size(); ++i) {
      if (arcs[i].arc == arcs[i - 1].arc)
        return Invalid("block ", b, ": arc ", arcs[i].arc, " appears twice in arcsByDir");
    }
    mesh_.block_arcs_.Append(arcs);

    std::vector<BlockNodeUvw> uvw;
    for (const v1::NodeUvw& entry : block.node_uvw()) {
      if (!ValidNode(entry.node()))
        return Invalid("block ", b, ": nodeUvw node ", entry.node(), " does not exist");
      if (entry.uvw_size() != 3)
        return Invalid("block ", b, ": nodeUvw of node ", entry.node(), " needs 3 coordinates");
      for (double x : entry.uvw()) {
        if (!std::isfinite(x))
          return Invalid("block ", b, ": nodeUvw of node ", entry.node(), " is not finite");
      }
      uvw.push_back({entry.node(), {entry.uvw(0), entry.uvw(1), entry.uvw(2)}});
    }
    std::sort(uvw.begin(), uvw.end(),
              [](const BlockNodeUvw& x, const BlockNodeUvw& y) { return x.node < y.node; });
    for (size_t i = 1; i < uvw.size(); ++i) {
      if (uvw[i].node == uvw[i - 1].node)
        return Invalid("block ", b, ": node ", uvw[i].node, " appears twice in nodeUvw");
    }
    mesh_.block_node_uvw_.Append(uvw);
    return absl::OkStatus();
  }

  // Every halfarc is listed exactly once, as outgoing of its tail.
  absl::Status CheckNodeArcIncidence() {
    std::vector<int> listed(2 * static_cast<size_t>(num_arcs_), 0);
    for (NodeId n = 0; n < num_nodes_; ++n) {
      for (HalfarcId h : mesh_.outgoing_halfarcs(n)) {
        if (mesh_.tail(h) != n)
          return Invalid("node ", n, ": outgoing halfarc ", h, " starts at node ", mesh_.tail(h));
        if (listed[h]++) return Invalid("node ", n, ": outgoing halfarc ", h, " listed twice");
      }
    }
    for (HalfarcId h = 0; h < 2 * num_arcs_; ++h) {
      if (!listed[h])
        return Invalid("node ", mesh_.tail(h), ": outgoing halfarc ", h, " is missing");
    }
    return absl::OkStatus();
  }

  // arcs[a].halfpatches is exactly the set of halfpatches whose cycle contains halfarc 2a.
  absl::Status CheckArcPatchIncidence() {
    std::vector<std::vector<HalfpatchId>> expected(num_arcs_);
    for (PatchId p = 0; p < num_patches_; ++p) {
      for (HalfarcId h : mesh_.patch_cycle(p)) expected[ArcOf(h)].push_back(2 * p + (h & 1));
    }
    for (ArcId a = 0; a < num_arcs_; ++a) {
      std::vector<HalfpatchId> listed(mesh_.arc_halfpatches(a).begin(),
                                      mesh_.arc_halfpatches(a).end());
      std::sort(listed.begin(), listed.end());
      std::sort(expected[a].begin(), expected[a].end());
      if (listed != expected[a]) {
        return Invalid("arc ", a, ": halfpatches [", absl::StrJoin(listed, ","),
                       "] differ from the patches whose cycles contain it [",
                       absl::StrJoin(expected[a], ","), "]");
      }
    }
    return absl::OkStatus();
  }

  // Patch sides, block halfpatch lists and block faces agree with each other.
  absl::Status CheckPatchBlockIncidence() {
    for (BlockId b = 0; b < num_blocks_; ++b) {
      for (HalfpatchId hp : mesh_.block_halfpatches(b)) {
        if (mesh_.halfpatch_block(hp) != b) {
          return Invalid("block ", b, ": lists halfpatch ", hp, " whose block is ",
                         mesh_.halfpatch_block(hp));
        }
      }
      for (Dir side : kAllDirs) {
        for (PatchId p : mesh_.block_face_patches(b, side)) {
          const int k = mesh_.patch_block(p, 0) == b ? 0 : (mesh_.patch_block(p, 1) == b ? 1 : -1);
          if (k < 0 || mesh_.patch_face_side(p, k) != side) {
            return Invalid("block ", b, ": face ", DirName(side), " lists patch ", p,
                           " which does not lie on that face of the block");
          }
        }
      }
    }
    for (PatchId p = 0; p < num_patches_; ++p) {
      for (int k = 0; k < 2; ++k) {
        const BlockId b = mesh_.patch_block(p, k);
        if (b == kNoId) continue;
        const auto hps = mesh_.block_halfpatches(b);
        if (std::find(hps.begin(), hps.end(), 2 * p + k) == hps.end()) {
          return Invalid("patch ", p, ": side ", k, " faces block ", b,
                         " but the block does not list halfpatch ", 2 * p + k);
        }
        const auto face = mesh_.block_face_patches(b, mesh_.patch_face_side(p, k));
        if (std::find(face.begin(), face.end(), p) == face.end()) {
          return Invalid("patch ", p, ": lies on face ", DirName(mesh_.patch_face_side(p, k)),
                         " of block ", b, " but that face does not list it");
        }
      }
    }
    return absl::OkStatus();
  }

  // Directions of cycle halfarcs: the sides run along their stated direction in the reference
  // block, every cycle lies in its blocks' faces, and transitions map one frame onto the other.
  absl::Status CheckPatchGeometry() {
    for (PatchId p = 0; p < num_patches_; ++p) {
      for (int k = 0; k < 2; ++k) {
        const BlockId b = mesh_.patch_block(p, k);
        if (b == kNoId) continue;
        for (HalfarcId h : mesh_.patch_cycle(p)) {
          const std::optional<Dir> d = mesh_.HalfarcDirInBlock(h, b);
          if (!d)
            return Invalid("patch ", p, ": arc ", ArcOf(h), " of its cycle is not on block ", b);
          if (AxisOf(*d) == AxisOf(mesh_.patch_face_side(p, k))) {
            return Invalid("patch ", p, ": arc ", ArcOf(h), " runs across face ",
                           DirName(mesh_.patch_face_side(p, k)), " of block ", b);
          }
        }
      }
      const BlockId ref = mesh_.patch_ref_block(p);
      for (int i = 0; i < 4; ++i) {
        const PatchSide side = mesh_.patch_side(p, i);
        for (HalfarcId h : side.halfarcs) {
          if (mesh_.HalfarcDirInBlock(h, ref) != side.dir) {
            return Invalid("patch ", p, ": halfarc ", h, " of side ", DirName(side.dir),
                           " does not run along ", DirName(side.dir), " in block ", ref);
          }
        }
      }
      const BlockId b0 = mesh_.patch_block(p, 0), b1 = mesh_.patch_block(p, 1);
      if (b0 == kNoId || b1 == kNoId) continue;
      const Rotation r = mesh_.patch_rotation(p);
      for (HalfarcId h : mesh_.patch_cycle(p)) {
        if (r.Apply(*mesh_.HalfarcDirInBlock(h, b0)) != *mesh_.HalfarcDirInBlock(h, b1)) {
          return Invalid("patch ", p, ": transition does not map the direction of arc ", ArcOf(h),
                         " in block ", b0, " to its direction in block ", b1);
        }
      }
    }
    // Each block's arcs are exactly the arcs of its halfpatches' cycles.
    for (BlockId b = 0; b < num_blocks_; ++b) {
      std::vector<ArcId> from_cycles;
      for (HalfpatchId hp : mesh_.block_halfpatches(b)) {
        for (HalfarcId h : mesh_.patch_cycle(PatchOf(hp))) from_cycles.push_back(ArcOf(h));
      }
      std::sort(from_cycles.begin(), from_cycles.end());
      from_cycles.erase(std::unique(from_cycles.begin(), from_cycles.end()), from_cycles.end());
      const auto arcs = mesh_.block_arcs(b);
      if (from_cycles.size() != arcs.size()) {
        return Invalid("block ", b, ": arcsByDir lists ", arcs.size(),
                       " arcs but its patches have ", from_cycles.size());
      }
      for (size_t i = 0; i < arcs.size(); ++i) {
        if (arcs[i].arc != from_cycles[i]) {
          return Invalid("block ", b, ": arc ", arcs[i].arc,
                         " in arcsByDir is on none of its patches");
        }
      }
    }
    return absl::OkStatus();
  }

  // Edges are chains from corner to corner along the positive running axis.
  absl::Status CheckBlockEdges() {
    for (BlockId b = 0; b < num_blocks_; ++b) {
      const v1::Block& block = proto_.blocks(b);
      for (const v1::Edge& e : block.edges()) {
        const int code = *EdgeFromUpstreamBits(e.edge());
        const int axis = EdgeAxis(code);
        const int first = axis == 0 ? 1 : 0, second = axis == 2 ? 1 : 2;
        const int low_corner = (((code & 1) ? 1 : 0) << first) | (((code & 2) ? 1 : 0) << second);
        const int high_corner = low_corner | (1 << axis);
        NodeId at = mesh_.block_corner(b, low_corner);
        for (int i = 0; i < e.halfarcs_size(); ++i) {
          const HalfarcId h = e.halfarcs(i);
          if (mesh_.tail(h) != at || mesh_.HalfarcDirInBlock(h, b) != MakeDir(axis, false)) {
            return Invalid("block ", b, ": edge ", v1::UVWDir_Name(e.edge()),
                           " is not a chain along its positive axis (at arc ", e.arcs(i), ")");
          }
          at = mesh_.head(h);
        }
        if (at != mesh_.block_corner(b, high_corner)) {
          return Invalid("block ", b, ": edge ", v1::UVWDir_Name(e.edge()),
                         " does not end at its corner node ", mesh_.block_corner(b, high_corner));
        }
      }
    }
    return absl::OkStatus();
  }

  const BlockNodeUvw* FindUvw(BlockId b, NodeId n) const {
    const auto list = mesh_.block_node_uvw(b);
    const auto it = std::lower_bound(list.begin(), list.end(), n,
                                     [](const BlockNodeUvw& e, NodeId id) { return e.node < id; });
    return it != list.end() && it->node == n ? &*it : nullptr;
  }

  // uvw(to) - uvw(from) = length * dir for every arc of every block (format section 6).
  absl::Status CheckBlockCoordinates() {
    for (BlockId b = 0; b < num_blocks_; ++b) {
      for (const BlockArc& ba : mesh_.block_arcs(b)) {
        const BlockNodeUvw* from = FindUvw(b, mesh_.arc_from(ba.arc));
        const BlockNodeUvw* to = FindUvw(b, mesh_.arc_to(ba.arc));
        if (!from || !to)
          return Invalid("block ", b, ": nodeUvw lacks an endpoint of arc ", ba.arc);
        const double length = mesh_.arc_length(ba.arc);
        double scale = 1.0;
        for (int i = 0; i < 3; ++i)
          scale = std::max({scale, std::abs(from->uvw[i]), std::abs(to->uvw[i])});
        for (int i = 0; i < 3; ++i) {
          const double expected = i == AxisOf(ba.dir) ? SignOf(ba.dir) * length : 0.0;
          if (std::abs(to->uvw[i] - from->uvw[i] - expected) > options_.length_tolerance * scale) {
            return Invalid("block ", b, ": arc ", ba.arc, " of length ", length, " along ",
                           DirName(ba.dir), " does not match the coordinates of its nodes");
          }
        }
      }
    }
    return absl::OkStatus();
  }

  absl::Status DeriveAdjacency() {
    // Nodes -> blocks, from the blocks' arcs.
    std::vector<std::vector<BlockId>> node_blocks(num_nodes_);
    for (BlockId b = 0; b < num_blocks_; ++b) {
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
    // Nodes -> halfpatches, from the cycles.
    std::vector<std::vector<HalfpatchId>> node_halfpatches(num_nodes_);
    for (PatchId p = 0; p < num_patches_; ++p) {
      for (HalfarcId h : mesh_.patch_cycle(p)) {
        node_halfpatches[mesh_.tail(h)].push_back(2 * p);
        node_halfpatches[mesh_.tail(h)].push_back(2 * p + 1);
      }
    }
    for (auto& list : node_halfpatches) {
      std::sort(list.begin(), list.end());
      mesh_.node_halfpatches_.Append(list);
    }
    // Arcs -> blocks in radial order; must equal the blocks that list the arc.
    std::vector<std::vector<BlockId>> listed_by_blocks(num_arcs_);
    for (BlockId b = 0; b < num_blocks_; ++b) {
      for (const BlockArc& ba : mesh_.block_arcs(b)) listed_by_blocks[ba.arc].push_back(b);
    }
    for (ArcId a = 0; a < num_arcs_; ++a) {
      std::vector<BlockId> radial;
      for (HalfpatchId hp : mesh_.arc_halfpatches(a)) {
        const BlockId b = mesh_.halfpatch_block(hp);
        if (b != kNoId && std::find(radial.begin(), radial.end(), b) == radial.end())
          radial.push_back(b);
      }
      std::vector<BlockId> sorted = radial;
      std::sort(sorted.begin(), sorted.end());
      if (sorted != listed_by_blocks[a]) {
        return Invalid("arc ", a, ": the blocks around it [", absl::StrJoin(sorted, ","),
                       "] differ from the blocks listing it in arcsByDir [",
                       absl::StrJoin(listed_by_blocks[a], ","), "]");
      }
      mesh_.arc_blocks_.Append(radial);
    }
    return absl::OkStatus();
  }

  // The boundary flag and whether the singular mark is non-zero follow from the blocks around
  // each arc (core/arc_singularity.h); criticality depends on both.
  absl::Status CheckArcSingularity() {
    const std::vector<int> quarter_turns = QuarterTurnsAroundArcs(mesh_);
    for (ArcId a = 0; a < num_arcs_; ++a) {
      const bool on_boundary = ArcOnBoundary(mesh_, a);
      if (mesh_.arc_boundary(a) != on_boundary) {
        return Invalid("arc ", a, ": boundary flag ", mesh_.arc_boundary(a), " but it ",
                       on_boundary ? "lies" : "does not lie", " on a boundary patch");
      }
      if (SingularByQuarterTurns(quarter_turns[a], on_boundary) != (mesh_.arc_singular(a) != 0)) {
        return Invalid("arc ", a, ": singular mark ", mesh_.arc_singular(a), " contradicts the ",
                       quarter_turns[a], " quarter turns of the blocks around this ",
                       on_boundary ? "boundary" : "interior", " arc (singular iff not ",
                       on_boundary ? 2 : 4, ")");
      }
    }
    return absl::OkStatus();
  }

  // Recomputes the critical-node rules (shared/separation.md section 2.1) and cross-checks the
  // file's flags: the search relies on them and a mismatch means the mesh was built differently.
  absl::Status CheckCriticalNodes() {
    std::vector<uint8_t> arc_on_feature_patch(num_arcs_, 0);
    std::vector<uint8_t> node_on_feature_patch(num_nodes_, 0);
    for (PatchId p = 0; p < num_patches_; ++p) {
      if (!mesh_.patch_feature(p)) continue;
      for (HalfarcId h : mesh_.patch_cycle(p)) {
        arc_on_feature_patch[ArcOf(h)] = 1;
        node_on_feature_patch[mesh_.tail(h)] = 1;
      }
    }
    const v1::FeaturesPresent& present = proto_.features_present();
    for (NodeId n = 0; n < num_nodes_; ++n) {
      int singular = 0, feature = 0;
      bool singular_non_feature = false, singular_off_feature_patches = false;
      for (HalfarcId h : mesh_.outgoing_halfarcs(n)) {
        const ArcId a = ArcOf(h);
        if (mesh_.arc_feature(a)) ++feature;
        if (mesh_.arc_singular(a) != 0) {
          ++singular;
          if (!mesh_.arc_feature(a)) singular_non_feature = true;
          if (!arc_on_feature_patch[a]) singular_off_feature_patches = true;
        }
      }
      bool critical = (singular != 0 && singular != 2) || mesh_.node_feature(n);
      if (present.arcs()) {
        critical =
            critical || (feature != 0 && feature != 2) || (feature == 2 && singular_non_feature);
      }
      if (present.patches()) {
        critical = critical || (feature == 0 && singular == 2 && node_on_feature_patch[n] &&
                                singular_off_feature_patches);
      }
      if (critical != mesh_.node_critical(n)) {
        return Invalid("node ", n, ": critical flag ", mesh_.node_critical(n),
                       " contradicts the criticality rules (", singular, " singular and ", feature,
                       " feature arcs)");
      }
    }
    return absl::OkStatus();
  }

  // The entities are derived from the mesh (core/critical_entities.h), never taken from the
  // request: the separation certificate depends on them. A request may leave the list out; a
  // list it sends must be the derived one.
  absl::Status DeriveCriticalEntities() {
    const std::vector<CriticalEntity> derived = ispq::DeriveCriticalEntities(mesh_);
    const int listed = proto_.critical_entities_size();
    if (listed != 0) {
      for (int e = 0; e < listed; ++e) {
        const v1::CriticalEntity& entity = proto_.critical_entities(e);
        if (entity.id() != e) return Invalid("critical entity ", e, ": id is ", entity.id());
        if (entity.dim() < 0 || entity.dim() > 2) {
          return Invalid("critical entity ", e, ": dim ", entity.dim(), " is not 0, 1 or 2");
        }
        const CriticalEntity given = EntityFromProto(entity);
        if (e >= static_cast<int>(derived.size())) {
          return Invalid("critical entity ", e, ": the mesh has only ", derived.size(),
                         " critical entities, the request lists ", listed);
        }
        if (!(given == derived[e])) {
          return Invalid("critical entity ", e, ": the mesh makes it ",
                         DescribeCriticalEntity(derived[e]), ", the request says ",
                         DescribeCriticalEntity(given));
        }
      }
      if (listed < static_cast<int>(derived.size())) {
        return Invalid("critical entity ", listed, ": missing from the request (the mesh makes it ",
                       DescribeCriticalEntity(derived[listed]), ")");
      }
    }
    for (const CriticalEntity& entity : derived) {
      mesh_.entity_dim_.push_back(entity.dim);
      mesh_.entity_nodes_.push_back({entity.node_from, entity.node_to});
      mesh_.entity_halfarcs_.Append(entity.halfarcs);
      mesh_.entity_patches_.Append(entity.patches);
      mesh_.entity_boundary_arcs_.Append(entity.boundary_arcs);
    }
    return absl::OkStatus();
  }

  static CriticalEntity EntityFromProto(const v1::CriticalEntity& proto) {
    CriticalEntity entity;
    entity.dim = proto.dim() == 1 ? EntityDim::kLink
                                  : (proto.dim() == 2 ? EntityDim::kRegion : EntityDim::kNode);
    if (entity.dim != EntityDim::kRegion) {
      entity.node_from = proto.node_from();
      entity.node_to = proto.node_to();
    }
    entity.halfarcs.assign(proto.halfarcs().begin(), proto.halfarcs().end());
    entity.patches.assign(proto.patches().begin(), proto.patches().end());
    entity.boundary_arcs.assign(proto.boundary_arcs().begin(), proto.boundary_arcs().end());
    return entity;
  }

  // Levels are optional; when present they must be the format's levels for these lengths.
  absl::Status LoadLevels() {
    for (int i = 0; i < proto_.levels_size(); ++i) {
      const v1::Level& level = proto_.levels(i);
      if (!IsLevelPercent(level.percent())) {
        return Invalid("level ", i, ": percent ", level.percent(),
                       " is not one of the format's levels");
      }
      const double expected = *ScalingForPercent(mesh_.arc_lengths(), level.percent());
      if (!std::isfinite(level.scaling()) ||
          std::abs(level.scaling() - expected) > 1e-9 * expected) {
        return Invalid("level ", i, ": scaling ", level.scaling(), " for ", level.percent(),
                       "% should be ", expected);
      }
      mesh_.levels_.push_back({level.percent(), level.scaling()});
    }
    return absl::OkStatus();
  }

  const v1::TMesh& proto_;
  const TMeshValidationOptions& options_;
  int num_nodes_ = 0, num_arcs_ = 0, num_patches_ = 0, num_blocks_ = 0;
  TMesh mesh_;
};

absl::StatusOr<TMesh> TMeshFromProto(const v1::TMesh& proto,
                                     const TMeshValidationOptions& options) {
  return TMeshAssembler(proto, options).Assemble();
}

}  // namespace ispq
