// SPDX-License-Identifier: Apache-2.0
// Reading T-mesh messages from files and strings: `*.tmesh.json` through protobuf's JSON
// mapping or binary protobuf (`*.tmesh.pb`), as proto/README.md, section Encodings, describes.
//
// This only parses; TMeshFromProto validates. Errors name the file and what failed to parse.
#ifndef ISPQ_CORE_PROTO_TMESH_FILE_H_
#define ISPQ_CORE_PROTO_TMESH_FILE_H_

#include <memory>
#include <string>
#include <string_view>

#include "absl/status/statusor.h"
#include "google/protobuf/arena.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq {

// Files larger than this are refused before they are read (the largest shared file is 0.3 MiB).
inline constexpr size_t kMaxTMeshFileBytes = size_t{256} << 20;

absl::StatusOr<v1::TMesh> ParseTMeshJson(std::string_view json);
absl::StatusOr<v1::TMesh> ParseTMeshBinary(std::string_view bytes);

// A T-mesh message on an arena of its own. A large mesh is millions of small sub-messages and
// repeated fields: carved from arena blocks they take a quarter less memory than as heap
// allocations of their own (98k arcs: 119 MiB against 164 MiB, next to a 44 MiB model), and
// loading peaks while the message and the model built from it coexist.
class TMeshMessage {
 public:
  TMeshMessage();

  const v1::TMesh& get() const { return *message_; }
  v1::TMesh* mutable_message() { return message_; }

  // A message on the same arena (say, the request that will carry the mesh): swapping the mesh
  // into it moves pointers instead of copying. It lives as long as this object.
  template <typename Message>
  Message* CreateOnArena() {
    return google::protobuf::Arena::CreateMessage<Message>(arena_.get());
  }

 private:
  std::unique_ptr<google::protobuf::Arena> arena_;
  v1::TMesh* message_;  // owned by arena_
};

// Whether a file of this name is binary protobuf: its name ends in ".pb" or ".binpb".
bool IsBinaryTMeshPath(const std::string& path);

// Binary or JSON as IsBinaryTMeshPath says.
absl::StatusOr<TMeshMessage> ReadTMeshFile(const std::string& path);

}  // namespace ispq

#endif  // ISPQ_CORE_PROTO_TMESH_FILE_H_
