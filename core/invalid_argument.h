// SPDX-License-Identifier: Apache-2.0
// InvalidArgument("arc ", a, ": length ", l, " is not ..."): the INVALID_ARGUMENT status of the
// concatenated pieces. Every rule the T-mesh checks and the decoder enforce reports this way, so
// that a message names the element first and the rule it breaks after it.
#ifndef ISPQ_CORE_INVALID_ARGUMENT_H_
#define ISPQ_CORE_INVALID_ARGUMENT_H_

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

namespace ispq {

template <typename... Pieces>
absl::Status InvalidArgument(const Pieces&... pieces) {
  return absl::InvalidArgumentError(absl::StrCat(pieces...));
}

}  // namespace ispq

#endif  // ISPQ_CORE_INVALID_ARGUMENT_H_
