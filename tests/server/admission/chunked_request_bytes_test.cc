// SPDX-License-Identifier: Apache-2.0
#include "server/admission/chunked_request_bytes.h"

#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "ispq/v1/service.pb.h"
#include "ispq/v1/tmesh.pb.h"

namespace ispq::server {
namespace {

std::string ReadAll(const RequestBytes& bytes) {
  std::string all;
  auto stream = bytes.Read();
  const void* data;
  int size;
  while (stream->Next(&data, &size)) all.append(static_cast<const char*>(data), size);
  EXPECT_EQ(stream->ByteCount(), static_cast<int64_t>(all.size()));
  return all;
}

TEST(ChunkedRequestBytesTest, ReadsTheChunksAsOneStreamEachTimeAnew) {
  const ChunkedRequestBytes bytes({"ab", "", "cde", "f"});
  EXPECT_EQ(bytes.size(), 6);
  EXPECT_EQ(ReadAll(bytes), "abcdef");
  EXPECT_EQ(ReadAll(bytes), "abcdef");
  EXPECT_EQ(ReadAll(ChunkedRequestBytes({})), "");
}

// Protobuf's parser backs up into a chunk and skips across chunk borders.
TEST(ChunkedRequestBytesTest, BacksUpAndSkipsAcrossChunks) {
  const ChunkedRequestBytes bytes({"abc", "defg", "hi"});
  auto stream = bytes.Read();
  const void* data;
  int size;
  ASSERT_TRUE(stream->Next(&data, &size));
  EXPECT_EQ(std::string(static_cast<const char*>(data), size), "abc");
  stream->BackUp(1);
  EXPECT_EQ(stream->ByteCount(), 2);
  ASSERT_TRUE(stream->Skip(3));  // "c", "de"
  ASSERT_TRUE(stream->Next(&data, &size));
  EXPECT_EQ(std::string(static_cast<const char*>(data), size), "fg");
  EXPECT_FALSE(stream->Skip(5));  // only "hi" is left
  EXPECT_FALSE(stream->Next(&data, &size));
}

// The upload's chunks behind the prefix are a CreateMeshRequest carrying the mesh, wherever the
// chunk borders fall (inside strings, varints, nested messages).
TEST(ChunkedRequestBytesTest, PrefixAndChunksParseAsACreateMeshRequest) {
  v1::TMesh mesh;
  mesh.set_format_version(1);
  mesh.set_name("a mesh whose name crosses chunk borders");
  for (int i = 0; i < 300; ++i) mesh.add_arcs()->set_length(0.5 + i);
  const std::string wire = mesh.SerializeAsString();
  for (const size_t chunk : {size_t{1}, size_t{7}, size_t{1000}, wire.size()}) {
    std::vector<std::string> chunks = {CreateMeshRequestPrefix(static_cast<int64_t>(wire.size()))};
    for (size_t offset = 0; offset < wire.size(); offset += chunk) {
      chunks.push_back(wire.substr(offset, chunk));
    }
    const ChunkedRequestBytes bytes(std::move(chunks));
    v1::CreateMeshRequest request;
    ASSERT_TRUE(request.ParseFromZeroCopyStream(bytes.Read().get())) << "chunks of " << chunk;
    EXPECT_EQ(request.mesh().SerializeAsString(), wire) << "chunks of " << chunk;
  }
}

TEST(ChunkedRequestBytesTest, ThePrefixIsTheMeshFieldsTagAndLength) {
  EXPECT_EQ(CreateMeshRequestPrefix(0), std::string("\x0a\x00", 2));
  EXPECT_EQ(CreateMeshRequestPrefix(300), "\x0a\xac\x02");  // 300 as a varint
  EXPECT_EQ(CreateMeshRequestPrefix(int64_t{1} << 30).size(), 1u + 5u);
}

}  // namespace
}  // namespace ispq::server
