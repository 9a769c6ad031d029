// SPDX-License-Identifier: Apache-2.0
#include "server/admission/request_bytes.h"

#include "google/protobuf/io/zero_copy_stream_impl_lite.h"

namespace ispq::server {

std::unique_ptr<google::protobuf::io::ZeroCopyInputStream> StringRequestBytes::Read() const {
  return std::make_unique<google::protobuf::io::ArrayInputStream>(bytes_.data(),
                                                                  static_cast<int>(bytes_.size()));
}

}  // namespace ispq::server
