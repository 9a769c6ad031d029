// SPDX-License-Identifier: Apache-2.0
#include "core/isp/parametric_layers.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <span>

#include "core/flat_lists.h"

namespace ispq {
namespace {

// Where a layer starts on its arc, as a fraction of the arc's length: off the middle, where
// regular spacings would put the iso-surface exactly through T-junction nodes (any choice there
// would still balance the row, but ties make layers of neighbouring arcs coincide).
constexpr double kStartFraction = 0.3819660112501051;
// A layer that closes crosses an arc at most a few times, all layers together 1.1-1.7 times per
// arc on the shared and synthetic meshes; a spiralling one would run on forever. So one layer may
// cross at most this many times the arcs, and the work of all layers (patch sides scanned, in
// halfarcs) is bounded by this many times the size of all patch cycles (at most 5.2 used there).
constexpr int64_t kLayerCrossingsPerArc = 4;
constexpr int64_t kWorkPerCycleHalfarc = 32;
// Sweeps of the multiplicity fit (coordinate descent; usually stable after two or three).
constexpr int kFitSweeps = 8;

// Follows iso-surfaces of the continuous parametrization through the patches.
class LayerTracer {
 public:
  explicit LayerTracer(const TMesh& mesh) : mesh_(mesh), balance_(3 * mesh.num_patches(), 0) {
    for (PatchId p = 0; p < mesh.num_patches(); ++p) {
      work_left_ += kWorkPerCycleHalfarc * static_cast<int64_t>(mesh.patch_cycle(p).size());
    }
  }

  // Follows the iso-surface through arc `start` at fraction `t` of it (from arc_from to arc_to),
  // appending every arc it crosses to `crossings` (an arc crossed k times, k times). False if it
  // had not closed after kLayerCrossingsPerArc crossings per arc, or once all layers together
  // used up their work.
  bool Trace(ArcId start, double t, std::vector<ArcId>* crossings) {
    const int64_t budget = kLayerCrossingsPerArc * mesh_.num_arcs();
    crossings->clear();
    Cross(start, t, crossings);
    bool closed = true;
    while (!pending_.empty()) {
      if (static_cast<int64_t>(crossings->size()) > budget || work_left_ < 0 || lost_) {
        closed = false;
        break;
      }
      const Pending entry = pending_.front();
      pending_.pop_front();
      const int32_t balance = balance_[3 * entry.patch + entry.axis];
      if (balance == 0) continue;  // another crossing balanced the row meanwhile
      // More crossings on the side running along +axis: cross the patch to the other side.
      const auto [arc, fraction] =
          ArcAt(entry.patch, MakeDir(entry.axis, balance > 0), entry.coordinate);
      if (arc == kNoId) {
        closed = false;
        break;
      }
      Cross(arc, fraction, crossings);
    }
    pending_.clear();
    for (int32_t row : touched_) balance_[row] = 0;
    touched_.clear();
    return closed && work_left_ >= 0 && !lost_;
  }

 private:
  struct Pending {
    PatchId patch;
    int axis;
    double coordinate;  // along `axis` in the patch's reference block frame
  };

  // The coordinate of node n along `axis` in block b's frame. A validated mesh has one for every
  // node on b's boundary; were it missing, the layer is lost and the tracing fails.
  double Coordinate(BlockId b, NodeId n, int axis) {
    const std::span<const BlockNodeUvw> uvw = mesh_.block_node_uvw(b);
    const auto it = std::lower_bound(uvw.begin(), uvw.end(), n,
                                     [](const BlockNodeUvw& x, NodeId id) { return x.node < id; });
    if (it == uvw.end() || it->node != n) {
      lost_ = true;
      return 0;
    }
    return it->uvw[axis];
  }

  // The layer crosses arc a at fraction t: every patch containing a gains a crossing on a's side.
  void Cross(ArcId a, double t, std::vector<ArcId>* crossings) {
    crossings->push_back(a);
    for (const HalfpatchId hp : mesh_.arc_halfpatches(a)) {
      const PatchId p = PatchOf(hp);
      const std::optional<Dir> dir = SideDirOf(p, a);
      if (!dir.has_value()) continue;
      const int axis = AxisOf(*dir);
      const int32_t row = 3 * p + axis;
      if (balance_[row] == 0) touched_.push_back(row);
      balance_[row] += SignOf(*dir);
      if (balance_[row] == 0) continue;  // this crossing balanced the row: nothing to follow
      const BlockId b = mesh_.patch_ref_block(p);
      const double from = Coordinate(b, mesh_.arc_from(a), axis);
      const double to = Coordinate(b, mesh_.arc_to(a), axis);
      pending_.push_back({p, axis, from + t * (to - from)});
    }
  }

  std::optional<Dir> SideDirOf(PatchId p, ArcId a) {
    for (int i = 0; i < 4; ++i) {
      const PatchSide side = mesh_.patch_side(p, i);
      work_left_ -= static_cast<int64_t>(side.halfarcs.size());
      for (const HalfarcId h : side.halfarcs) {
        if (ArcOf(h) == a) return side.dir;
      }
    }
    return std::nullopt;
  }

  // The arc of patch p's side running along `dir` that spans `coordinate` (the nearest one if
  // rounding left it between two), and the fraction of it where the coordinate lies.
  std::pair<ArcId, double> ArcAt(PatchId p, Dir dir, double coordinate) {
    const BlockId b = mesh_.patch_ref_block(p);
    const int axis = AxisOf(dir);
    ArcId best = kNoId;
    double best_distance = INFINITY, best_fraction = 0;
    for (int i = 0; i < 4; ++i) {
      const PatchSide side = mesh_.patch_side(p, i);
      if (side.dir != dir) continue;
      work_left_ -= static_cast<int64_t>(side.halfarcs.size());
      // Consecutive halfarcs of a side share a node (unless the side wraps around the start of
      // the cycle): its coordinate is looked up once.
      NodeId head = kNoId;
      double at_head = 0;
      for (const HalfarcId h : side.halfarcs) {
        const ArcId a = ArcOf(h);
        const double at_tail = mesh_.tail(h) == head ? at_head : Coordinate(b, mesh_.tail(h), axis);
        head = mesh_.head(h);
        at_head = Coordinate(b, head, axis);
        const double from = (h & 1) ? at_head : at_tail;  // at arc_from
        const double to = (h & 1) ? at_tail : at_head;    // at arc_to
        const double fraction = std::clamp((coordinate - from) / (to - from), 0.0, 1.0);
        const double distance = std::abs(from + fraction * (to - from) - coordinate);
        if (distance < best_distance) {
          best = a;
          best_distance = distance;
          best_fraction = fraction;
          if (distance == 0) return {best, best_fraction};
        }
      }
    }
    return {best, best_fraction};
  }

  const TMesh& mesh_;
  std::vector<int32_t> balance_;  // per (patch, axis): crossings on the +axis side minus -axis
  std::vector<int32_t> touched_;
  std::deque<Pending> pending_;
  int64_t work_left_ = 0;
  bool lost_ = false;  // a node had no coordinates
};

struct LayerTerm {
  BundleId bundle;
  int32_t count;  // crossings of each arc of the bundle
};

// Each layer's crossings per bundle; false if some bundle's arcs were crossed unequally (the
// parametrization disagrees with the bundles, which no valid T-mesh does).
bool AppendLayer(std::span<const ArcId> crossings, const ArcBundles& bundles,
                 std::vector<int32_t>& arc_count, FlatLists<LayerTerm>& layers) {
  for (const ArcId a : crossings) ++arc_count[a];
  layers.OpenList();
  bool equal = true;
  for (const ArcId a : crossings) {
    if (arc_count[a] == 0) continue;  // its bundle is done
    const BundleId b = bundles.bundle_of(a);
    const int32_t count = arc_count[a];
    for (const ArcId other : bundles.arcs(b)) {
      equal &= arc_count[other] == count;
      arc_count[other] = 0;
    }
    layers.PushToLast({b, count});
  }
  return equal;
}

// Multiplicities t_k >= 1 of the layers by coordinate descent on the objective: for one layer
// with the others fixed, the objective is a quadratic in t_k with its minimum at num / den.
std::vector<int64_t> FitMultiplicities(const FlatLists<LayerTerm>& layers,
                                       const BundleQuantization& quantization) {
  std::vector<int64_t> values(quantization.num_bundles(), 0);
  std::vector<int64_t> multiplicity(layers.size(), 1);
  for (int k = 0; k < layers.size(); ++k) {
    for (const LayerTerm& term : layers[k]) values[term.bundle] += term.count;
  }
  for (int sweep = 0; sweep < kFitSweeps; ++sweep) {
    bool changed = false;
    for (int k = 0; k < layers.size(); ++k) {
      double num = 0, den = 0;
      for (const LayerTerm& term : layers[k]) {
        const double m = quantization.arc_count(term.bundle);
        const double rest = static_cast<double>(values[term.bundle] - multiplicity[k] * term.count);
        num += term.count * (quantization.target_sum(term.bundle) - m * rest);
        den += m * term.count * term.count;
      }
      const int64_t best = std::max<int64_t>(1, std::llround(num / den));
      if (best == multiplicity[k]) continue;
      for (const LayerTerm& term : layers[k]) {
        values[term.bundle] += (best - multiplicity[k]) * term.count;
      }
      multiplicity[k] = best;
      changed = true;
    }
    if (!changed) break;
  }
  return values;
}

}  // namespace

std::optional<std::vector<int64_t>> QuantizeByParametricLayers(
    const TMesh& mesh, const ArcBundles& bundles, const BundleQuantization& quantization) {
  const int64_t arcs = mesh.num_arcs();
  LayerTracer tracer(mesh);
  std::vector<uint8_t> crossed(arcs, 0);
  std::vector<int32_t> arc_count(arcs, 0);
  std::vector<ArcId> crossings;
  FlatLists<LayerTerm> layers;
  for (ArcId a = 0; a < arcs; ++a) {
    if (crossed[a]) continue;
    if (!tracer.Trace(a, kStartFraction, &crossings)) return std::nullopt;
    for (const ArcId c : crossings) crossed[c] = 1;
    if (!AppendLayer(crossings, bundles, arc_count, layers)) return std::nullopt;
  }
  return FitMultiplicities(layers, quantization);
}

}  // namespace ispq
