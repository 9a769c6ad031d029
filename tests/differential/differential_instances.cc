// SPDX-License-Identifier: Apache-2.0
// Writes the quantizations the differential harness checks on one T-mesh (README.md here), one
// JSON object per line: {"kind", "scaling", "q"}. Kinds:
//   final         ISP's result at a scaling (the 8 levels, then `random_scalings` log-uniform
//                 draws between half the level-0 factor and twice the level-100 factor);
//   intermediate  ISP's iterates on the way there (every `intermediate_stride`-th progress event
//                 whose q changed, and every one whose q the pump itself calls separating);
//   perturbed     a final q plus a small random consistent change (a few free arcs of the
//                 consistency system moved by -1..+1), which mostly keeps the simple rows and
//                 often breaks separation;
//   layered       the q of the parametrization's layers at the scaling
//   (core/isp/parametric_layers.h),
//                 which large runs report as their first valid q, where the layers close.
// Deterministic for a given seed.
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <iostream>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "absl/flags/flag.h"
#include "absl/flags/parse.h"
#include "absl/strings/str_join.h"
#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/isp/bundle_quantization.h"
#include "core/isp/parametric_layers.h"
#include "core/proto/tmesh_file.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/quantizer.h"
#include "tests/support/consistent_quantizations.h"

ABSL_FLAG(std::string, tmesh, "", "the T-mesh file");
ABSL_FLAG(int, random_scalings, 20, "random scalings besides the 8 levels");
ABSL_FLAG(int, intermediate_stride, 10, "keep every n-th distinct intermediate q");
ABSL_FLAG(int, perturbations, 2, "perturbed copies of each final q");
ABSL_FLAG(uint64_t, seed, 1, "random seed");

namespace ispq {
namespace {

void Emit(const char* kind, double scaling, std::span<const int64_t> q) {
  std::cout << "{\"kind\":\"" << kind << "\",\"scaling\":" << std::setprecision(17) << scaling
            << ",\"q\":[" << absl::StrJoin(q, ",") << "]}\n";
}

// Keeps a thinned-out sequence of the pump's distinct iterates.
class IterateSampler : public ProgressObserver {
 public:
  explicit IterateSampler(int stride) : stride_(stride) {}
  bool WantsQuantization() const override { return true; }
  void OnProgress(const ProgressEvent& event) override {
    if (std::vector<int64_t>(event.q.begin(), event.q.end()) == last_) return;
    last_.assign(event.q.begin(), event.q.end());
    if (event.separating || ++distinct_ % stride_ == 0) kept_.push_back(last_);
  }
  const std::vector<std::vector<int64_t>>& kept() const { return kept_; }

 private:
  int stride_;
  int distinct_ = 0;
  std::vector<int64_t> last_;
  std::vector<std::vector<int64_t>> kept_;
};

int Run() {
  absl::StatusOr<TMeshMessage> proto = ReadTMeshFile(absl::GetFlag(FLAGS_tmesh));
  if (!proto.ok()) {
    std::cerr << proto.status() << "\n";
    return 2;
  }
  absl::StatusOr<TMesh> mesh = TMeshFromProto(proto->get());
  if (!mesh.ok()) {
    std::cerr << mesh.status() << "\n";
    return 2;
  }
  std::mt19937_64 random(absl::GetFlag(FLAGS_seed));
  std::vector<double> scalings;
  for (const Level& level : mesh->levels()) scalings.push_back(level.scaling);
  const double low = std::log(0.5 * scalings.front());
  const double high = std::log(2 * scalings.back());
  for (int i = 0; i < absl::GetFlag(FLAGS_random_scalings); ++i) {
    scalings.push_back(std::exp(std::uniform_real_distribution<double>(low, high)(random)));
  }

  const testing::ConsistentQuantizations consistent(*mesh);
  const std::span<const ArcId> free_arcs = consistent.free_arcs();
  const ConsistencyMatrix consistency(*mesh);
  const ArcBundles bundles(*mesh, consistency);
  for (double scaling : scalings) {
    const std::optional<std::vector<int64_t>> layered =
        QuantizeByParametricLayers(*mesh, bundles, BundleQuantization(*mesh, bundles, scaling));
    if (layered.has_value()) Emit("layered", scaling, bundles.ArcValues(*layered));
    QuantizeOptions options;
    options.scaling = scaling;
    IterateSampler sampler(absl::GetFlag(FLAGS_intermediate_stride));
    absl::StatusOr<QuantizeResult> result = Quantize(*mesh, options, &sampler);
    if (!result.ok()) {
      std::cerr << "scaling " << scaling << ": " << result.status() << "\n";
      return 1;
    }
    Emit("final", scaling, result->q);
    for (const std::vector<int64_t>& q : sampler.kept()) Emit("intermediate", scaling, q);
    for (int i = 0; i < absl::GetFlag(FLAGS_perturbations) && !free_arcs.empty(); ++i) {
      std::vector<int64_t> delta_free(free_arcs.size(), 0);
      const int moves = 1 + static_cast<int>(random() % 3);
      for (int m = 0; m < moves; ++m) {
        delta_free[random() % free_arcs.size()] = static_cast<int64_t>(random() % 3) - 1;
      }
      const std::vector<int64_t> delta = consistent.Extend(delta_free);
      std::vector<int64_t> q = result->q;
      for (size_t a = 0; a < q.size(); ++a) q[a] += delta[a];
      Emit("perturbed", scaling, q);
    }
  }
  return 0;
}

}  // namespace
}  // namespace ispq

int main(int argc, char** argv) {
  absl::ParseCommandLine(argc, argv);
  return ispq::Run();
}
