// Validation of an ispq.v1.TMesh message and its conversion into the core TMesh model.
//
// This is the only door into core/: every rule of shared/tmesh-format.md that the algorithms rely
// on is checked here, once, so that the quantizer and the separation search can index arrays
// without further checks. A rejected mesh yields INVALID_ARGUMENT naming the offending element
// and the rule it breaks (e.g. "patch 12: ..."). Hostile input (ids of 2^31, NaN lengths,
// truncated lists) is rejected before anything is allocated from it.
#ifndef ISPQ_CORE_PROTO_TMESH_FROM_PROTO_H_
#define ISPQ_CORE_PROTO_TMESH_FROM_PROTO_H_

#include "absl/status/statusor.h"
#include "core/tmesh.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq {

struct TMeshValidationOptions {
  // Relative tolerance for continuous-length identities: opposite patch sides, and
  // uvw(to) - uvw(from) = length * dir for every arc of a block.
  double length_tolerance = 1e-6;
};

absl::StatusOr<TMesh> TMeshFromProto(const v1::TMesh& proto,
                                     const TMeshValidationOptions& options = {});

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_TMESH_FROM_PROTO_H_
