// SPDX-License-Identifier: Apache-2.0
#include "core/quantization_objective.h"

namespace ispq {

double QuantizationObjective(const TMesh& mesh, std::span<const int64_t> q, double scaling) {
  double objective = 0;
  for (ArcId a = 0; a < mesh.num_arcs(); ++a) {
    const double d = static_cast<double>(q[a]) - scaling * mesh.arc_length(a);
    objective += d * d;
  }
  return objective;
}

}  // namespace ispq
