// SPDX-License-Identifier: Apache-2.0
// Conversions between the ispq.v1 quantization messages (proto/ispq/v1/quantization.proto) and
// the core types: options in (with the scaling resolved against the mesh), results and progress
// out. The CLI's local path, its result files and the service all go through these, so a result
// looks the same wherever it was computed.
#ifndef ISPQ_CORE_PROTO_QUANTIZATION_PROTO_H_
#define ISPQ_CORE_PROTO_QUANTIZATION_PROTO_H_

#include <cstdint>
#include <vector>

#include "absl/status/statusor.h"
#include "core/quantization_progress.h"
#include "core/quantizer.h"
#include "core/scaling.h"
#include "core/tmesh.h"
#include "ispq/v1/quantization.pb.h"

namespace ispq {

// The caller's choice of s, resolved by ResolveScaling (core/scaling.h); unset if the message
// sets none.
ScalingChoice ScalingChoiceFromProto(const v1::Scaling& scaling);

// Options with the scaling resolved against the mesh; INVALID_ARGUMENT names a bad scaling or
// option.
absl::StatusOr<QuantizeOptions> QuantizeOptionsFromProto(const v1::QuantizationOptions& proto,
                                                         const TMesh& mesh);

v1::QuantizationResult QuantizationResultToProto(const QuantizeResult& result, double scaling,
                                                 const TMesh& mesh);

v1::Progress ProgressToProto(const ProgressEvent& event);

// q of a result message, checked against the mesh (one entry per arc).
absl::StatusOr<std::vector<int64_t>> QuantizationFromProto(const v1::QuantizationResult& result,
                                                           const TMesh& mesh);

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_QUANTIZATION_PROTO_H_
