// SPDX-License-Identifier: Apache-2.0
#include "tests/support/enumerated_optimum.h"

#include <algorithm>
#include <cmath>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "core/arc_bundles.h"
#include "core/consistency_matrix.h"
#include "core/quantization_validator.h"

namespace ispq::testing {

double QuantizationObjective(const TMesh& mesh, double scaling, const std::vector<int64_t>& q) {
  double sum = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    sum += std::pow(static_cast<double>(q[a]) - scaling * mesh.arc_length(a), 2);
  }
  return sum;
}

absl::StatusOr<EnumeratedOptimum> EnumerateOptimum(const TMesh& mesh, double scaling, int radius) {
  const ConsistencyMatrix consistency(mesh);
  const ArcBundles bundles(mesh, consistency);
  const int nb = bundles.num_bundles();
  std::vector<int64_t> low(nb), count(nb);
  double combinations = 1;
  for (BundleId b = 0; b < nb; ++b) {
    double mean = 0;
    for (ArcId a : bundles.arcs(b)) mean += scaling * mesh.arc_length(a);
    mean /= static_cast<double>(bundles.arcs(b).size());
    low[b] = std::max<int64_t>(0, std::llround(mean) - radius);
    count[b] = std::llround(mean) + radius - low[b] + 1;
    combinations *= static_cast<double>(count[b]);
  }
  if (combinations > 5e6) {
    return absl::ResourceExhaustedError(
        absl::StrCat("too many candidates to enumerate: ", combinations));
  }
  std::vector<EnumeratedOptimum> consistent;
  std::vector<int64_t> digit(nb, 0), q(mesh.num_arcs());
  while (true) {
    for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
      const BundleId b = bundles.bundle_of(a);
      q[a] = low[b] + digit[b];
    }
    bool ok = true;
    for (int r = 0; r < consistency.num_rows() && ok; ++r) ok = consistency.RowValue(r, q) == 0;
    if (ok) consistent.push_back({QuantizationObjective(mesh, scaling, q), q});
    int b = 0;
    while (b < nb && ++digit[b] == count[b]) digit[b++] = 0;
    if (b == nb) break;
  }
  std::sort(consistent.begin(), consistent.end(),
            [](const EnumeratedOptimum& x, const EnumeratedOptimum& y) {
              return x.objective < y.objective;
            });
  for (const EnumeratedOptimum& candidate : consistent) {
    const absl::StatusOr<ValidationReport> report = ValidateQuantization(mesh, candidate.q);
    if (report.ok() && report->valid()) return candidate;
  }
  return absl::NotFoundError("no valid quantization within the radius");
}

}  // namespace ispq::testing
