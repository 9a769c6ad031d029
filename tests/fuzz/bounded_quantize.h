// SPDX-License-Identifier: Apache-2.0
// What every fuzz target does with a mesh that passed the loader: quantize it within a small
// time limit at the requested options and hold the result to the validator. A crash, a sanitizer
// report or a result that calls itself valid but is not (trap) is a finding.
#ifndef ISPQ_TESTS_FUZZ_BOUNDED_QUANTIZE_H_
#define ISPQ_TESTS_FUZZ_BOUNDED_QUANTIZE_H_

#include "core/quantizer.h"
#include "core/tmesh.h"

namespace ispq::fuzz {

// Meshes larger than this are only loaded, not quantized, so that each input stays fast.
inline constexpr int kMaxArcsToQuantize = 400;

void QuantizeBounded(const TMesh& mesh, QuantizeOptions options);

}  // namespace ispq::fuzz

#endif  // ISPQ_TESTS_FUZZ_BOUNDED_QUANTIZE_H_
