// Conversions between the ispq.v1 quantization messages (proto/ispq/v1/quantization.proto) and
// the core types: options in (with the scaling resolved against the mesh), results and progress
// out. The CLI's local path, its result files and the service all go through these, so a result
// looks the same wherever it was computed.
#ifndef ISPQ_CORE_QUANTIZATION_PROTO_H_
#define ISPQ_CORE_QUANTIZATION_PROTO_H_

#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "core/quantization_progress.h"
#include "core/quantizer.h"
#include "core/tmesh.h"
#include "ispq/v1/quantization.pb.h"

namespace ispq {

// The factor s of a Scaling: the factor itself, a level's factor (format section 9), or the
// factor whose continuous block volume is the target hex count. INVALID_ARGUMENT if unset,
// non-positive, non-finite or not one of the format's levels.
absl::StatusOr<double> ResolveScaling(const v1::Scaling& scaling, const TMesh& mesh);

absl::StatusOr<QuantizeOptions> QuantizeOptionsFromProto(const v1::QuantizationOptions& proto,
                                                         const TMesh& mesh);

v1::QuantizationResult QuantizationResultToProto(const QuantizeResult& result, double scaling,
                                                 const TMesh& mesh);

v1::Progress ProgressToProto(const ProgressEvent& event);

// q of a result message, checked against the mesh (one entry per arc).
absl::StatusOr<std::vector<int64_t>> QuantizationFromProto(const v1::QuantizationResult& result,
                                                           const TMesh& mesh);

}  // namespace ispq

#endif  // ISPQ_CORE_QUANTIZATION_PROTO_H_
