// SPDX-License-Identifier: Apache-2.0
#include "server/grpc/raw_proto_call.h"

namespace ispq::server {

grpc::Status SerializeMessage(const google::protobuf::MessageLite& message, grpc::ByteBuffer& raw) {
  raw.Clear();  // the writer requires an empty buffer (streams reuse theirs)
  bool own_buffer = false;
  return grpc::SerializationTraits<google::protobuf::MessageLite>::Serialize(message, &raw,
                                                                             &own_buffer);
}

}  // namespace ispq::server
