// SPDX-License-Identifier: Apache-2.0
#include "core/quantization_limits.h"

#include "absl/strings/str_cat.h"
#include "core/block_extents.h"

namespace ispq {

absl::Status CheckTargetsRepresentable(const TMesh& mesh, double scaling) {
  ArcId longest = 0;
  for (ArcId a = 1; a < mesh.num_arcs(); ++a) {
    if (mesh.arc_length(a) > mesh.arc_length(longest)) longest = a;
  }
  const double target = scaling * mesh.arc_length(longest);
  if (!(target <= kMaxTargetLength)) {
    return absl::InvalidArgumentError(absl::StrCat("scaling ", scaling, " gives arc ", longest,
                                                   " the target length ", target,
                                                   ", above the limit of ", kMaxTargetLength));
  }
  const double hexes = scaling * scaling * scaling * ContinuousHexVolume(mesh);
  if (!(hexes <= kMaxTargetHexes)) {
    return absl::InvalidArgumentError(absl::StrCat("scaling ", scaling, " asks for about ", hexes,
                                                   " hexes, above the limit of ", kMaxTargetHexes));
  }
  return absl::OkStatus();
}

}  // namespace ispq
