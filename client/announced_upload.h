// SPDX-License-Identifier: Apache-2.0
// The CLI's use of QuantizerClient::UploadIfLarge (client/quantizer_client.h): a mesh above the
// threshold is uploaded in chunks before its job is sent, and the user is told so on stderr, since
// a 264 MB upload takes seconds before the job's first event.
#ifndef ISPQ_CLIENT_ANNOUNCED_UPLOAD_H_
#define ISPQ_CLIENT_ANNOUNCED_UPLOAD_H_

#include <cstdint>
#include <string>

#include "absl/status/statusor.h"
#include "client/quantizer_client.h"
#include "ispq/v1/service.pb.h"

namespace ispq::cli {

// client.UploadIfLarge, saying on stderr (if `progress`) that a large mesh is being uploaded.
absl::StatusOr<std::string> UploadIfLarge(client::QuantizerClient& client,
                                          v1::QuantizeRequest& request, int64_t above_bytes,
                                          bool progress);

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_ANNOUNCED_UPLOAD_H_
