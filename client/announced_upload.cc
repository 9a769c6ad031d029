// SPDX-License-Identifier: Apache-2.0
#include "client/announced_upload.h"

#include <cstdio>

namespace ispq::cli {

absl::StatusOr<std::string> UploadIfLarge(client::QuantizerClient& client,
                                          v1::QuantizeRequest& request, int64_t above_bytes,
                                          bool progress) {
  const int64_t bytes =
      request.has_mesh() ? static_cast<int64_t>(request.mesh().ByteSizeLong()) : 0;
  if (progress && bytes > above_bytes) {
    std::fprintf(stderr, "uploading the mesh (%.1f MB) in chunks\n",
                 static_cast<double>(bytes) / 1e6);
  }
  return client.UploadIfLarge(request, above_bytes);
}

}  // namespace ispq::cli
