// SPDX-License-Identifier: Apache-2.0
// Decoding T-mesh bytes one element at a time (core/proto/tmesh_from_wire.h): every real mesh
// decodes to the mesh the whole message decodes to; bytes that are no T-mesh, element lists out
// of field order and the caller's bound on the counts are handled as the header says. (The table
// of corrupted meshes in tmesh_from_proto_test.cc checks both decoders give the same errors.)
#include "core/proto/tmesh_from_wire.h"

#include <memory>
#include <string>
#include <vector>

#include "core/proto/tmesh_from_proto.h"
#include "gmock/gmock.h"
#include "google/protobuf/io/zero_copy_stream_impl_lite.h"
#include "gtest/gtest.h"
#include "tests/core/proto/same_tmesh.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

// Reads `bytes` in pieces of `piece` bytes, as chunks of an upload arrive; counts the passes.
struct Bytes {
  std::string bytes;
  int piece = 1 << 20;
  mutable int reads = 0;
  TMeshBytesReader reader() const {
    return [this] {
      ++reads;
      return std::make_unique<google::protobuf::io::ArrayInputStream>(
          bytes.data(), static_cast<int>(bytes.size()), piece);
    };
  }
};

TEST(TMeshFromWireTest, EveryRealMeshDecodesAsTheWholeMessageDoes) {
  const std::vector<std::string> files = testing::RealTMeshFiles();
  ASSERT_EQ(files.size(), 62u);
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const v1::TMesh proto = testing::LoadProtoOrDie(file);
    const absl::StatusOr<TMesh> whole = TMeshFromProto(proto);
    ASSERT_TRUE(whole.ok()) << whole.status();
    Bytes bytes{.bytes = proto.SerializeAsString(), .piece = 4096};
    std::vector<std::vector<double>> positions;  // what the caller sees of each node, in order
    const absl::StatusOr<TMesh> streamed =
        TMeshFromWire(bytes.reader(), {.on_node = [&positions](const v1::Node& node) {
                        positions.emplace_back(node.position().begin(), node.position().end());
                      }});
    ASSERT_TRUE(streamed.ok()) << streamed.status();
    EXPECT_EQ(bytes.reads, 2) << "one pass to count, one to decode";
    testing::ExpectSameTMesh(*whole, *streamed);
    ASSERT_EQ(positions.size(), static_cast<size_t>(proto.nodes_size()));
    for (int n = 0; n < proto.nodes_size(); ++n) {
      ASSERT_EQ(positions[n], std::vector<double>(proto.nodes(n).position().begin(),
                                                  proto.nodes(n).position().end()))
          << "node " << n;
    }
  }
}

TEST(TMeshFromWireTest, TheCallerSeesTheCountsFirstAndMayStopThere) {
  const v1::TMesh proto =
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  Bytes bytes{.bytes = proto.SerializeAsString()};
  TMeshWireCounts seen;
  const absl::StatusOr<TMesh> refused =
      TMeshFromWire(bytes.reader(), {.check_counts = [&seen](const TMeshWireCounts& counts) {
                      seen = counts;
                      return absl::InvalidArgumentError("too many arcs");
                    }});
  EXPECT_EQ(refused.status(), absl::InvalidArgumentError("too many arcs"));
  EXPECT_EQ(bytes.reads, 1) << "refused before the elements were decoded";
  EXPECT_EQ(seen.nodes, proto.nodes_size());
  EXPECT_EQ(seen.arcs, proto.arcs_size());
  EXPECT_EQ(seen.patches, proto.patches_size());
  EXPECT_EQ(seen.blocks, proto.blocks_size());
}

// Protobuf lets a repeated field's entries come anywhere in a message; no serializer interleaves
// the element lists, but bytes that do still decode (parsed whole), to the same mesh.
TEST(TMeshFromWireTest, InterleavedElementListsDecodeAsTheMessage) {
  const v1::TMesh proto =
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  v1::TMesh first_node_last = proto;
  first_node_last.clear_nodes();
  v1::TMesh one_node;
  *one_node.add_nodes() = proto.nodes(0);
  v1::TMesh rest_of_nodes;
  for (int n = 1; n < proto.nodes_size(); ++n) *rest_of_nodes.add_nodes() = proto.nodes(n);
  // Node 0, the arcs and everything else, then nodes 1.. : parsed, that is the original mesh.
  Bytes bytes{.bytes = one_node.SerializeAsString() + first_node_last.SerializeAsString() +
                       rest_of_nodes.SerializeAsString()};
  v1::TMesh parsed;
  ASSERT_TRUE(parsed.ParseFromString(bytes.bytes));
  ASSERT_EQ(parsed.nodes_size(), proto.nodes_size());
  int nodes_seen = 0;
  const absl::StatusOr<TMesh> streamed =
      TMeshFromWire(bytes.reader(), {.on_node = [&](const v1::Node& node) {
                      EXPECT_EQ(node.position(0), proto.nodes(nodes_seen).position(0));
                      ++nodes_seen;
                    }});
  ASSERT_TRUE(streamed.ok()) << streamed.status();
  EXPECT_EQ(nodes_seen, proto.nodes_size()) << "each node seen once, in id order";
  const absl::StatusOr<TMesh> whole = TMeshFromProto(proto);
  ASSERT_TRUE(whole.ok());
  testing::ExpectSameTMesh(*whole, *streamed);
}

// Protobuf's parser takes a field with an element list's number but another wire type for an
// unknown field and ignores it: so does this decoder.
TEST(TMeshFromWireTest, AnElementFieldOfAnotherWireTypeIsIgnoredAsTheParserDoes) {
  const v1::TMesh proto =
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  // Field 8 (arcs) as a varint of value 5: tag (8 << 3) | 0.
  const Bytes bytes{.bytes = proto.SerializeAsString() + std::string("\x40\x05", 2)};
  v1::TMesh parsed;
  ASSERT_TRUE(parsed.ParseFromString(bytes.bytes));
  EXPECT_EQ(parsed.arcs_size(), proto.arcs_size());
  const absl::StatusOr<TMesh> streamed = TMeshFromWire(bytes.reader());
  ASSERT_TRUE(streamed.ok()) << streamed.status();
  const absl::StatusOr<TMesh> whole = TMeshFromProto(parsed);
  ASSERT_TRUE(whole.ok());
  testing::ExpectSameTMesh(*whole, *streamed);
}

// A tag whose varint does not fit in 32 bits is refused by protobuf's parser; read 32 bits at a
// time it would name another, valid field (found by tmesh_wire_fuzzer: a mesh with such a tag
// appended decoded here). Field 0 is refused too.
TEST(TMeshFromWireTest, TagsTheParserRefusesAreRefused) {
  const v1::TMesh proto =
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  // A tag of 36 bits whose low 32 name field 2^29 - 1 as a varint, with value 1; field 0.
  for (const std::string& bad :
       {std::string("\xf8\xff\xff\xff\xff\x01\x01", 7), std::string("\x02\x00", 2)}) {
    const Bytes bytes{.bytes = proto.SerializeAsString() + bad};
    v1::TMesh parsed;
    ASSERT_FALSE(parsed.ParseFromString(bytes.bytes));
    const absl::StatusOr<TMesh> result = TMeshFromWire(bytes.reader());
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(std::string(result.status().message()), HasSubstr("not a binary T-mesh"));
  }
}

TEST(TMeshFromWireTest, BytesThatAreNoTMeshAreRefusedSayingSo) {
  const v1::TMesh proto =
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
  const std::string whole = proto.SerializeAsString();
  for (const std::string& bad : {whole.substr(0, whole.size() / 2), std::string(5000, '\xff'),
                                 std::string("\x3a\x05\x08")}) {
    Bytes bytes{.bytes = bad};
    const absl::StatusOr<TMesh> result = TMeshFromWire(bytes.reader());
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument);
    EXPECT_THAT(std::string(result.status().message()), HasSubstr("not a binary T-mesh"));
  }
  // An element that is no message of its kind: a node whose position is a string.
  v1::TMesh broken_node;
  broken_node.add_nodes();
  std::string bytes = broken_node.SerializeAsString();  // field 7, length 0
  bytes += std::string("\x3a\x03\x0a\x01\x80", 5);      // field 7: a node with a cut-off varint
  const absl::StatusOr<TMesh> result = TMeshFromWire(Bytes{.bytes = bytes}.reader());
  EXPECT_EQ(result.status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace ispq
