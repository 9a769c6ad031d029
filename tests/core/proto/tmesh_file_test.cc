// SPDX-License-Identifier: Apache-2.0
// Reading T-mesh messages: JSON and binary documents parse to the same message and round-trip,
// the file's name picks the format, malformed documents are refused with a message that names
// the file, and a missing file is NOT_FOUND. (Validation of what was read is TMeshFromProto's,
// tests/core/proto/tmesh_from_proto_test.cc.)
#include "core/proto/tmesh_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "core/read_file.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;

// A real mesh with interior patches and non-identity transitions.
const v1::TMesh& Tetrahedron() {
  static const v1::TMesh* const kMesh = new v1::TMesh(
      testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s04u_tetrahedron.tmesh.json")));
  return *kMesh;
}

// A fresh folder of this process for one test.
std::filesystem::path TempDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("ispq-tmesh-file-" + std::to_string(::getpid()) + "-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Corruptions of the JSON text itself: the parser must reject them with a clear message and
// never crash or allocate from a hostile value.
struct JsonCorruption {
  std::string name;
  std::function<std::string(const std::string&)> mutate;
  std::string expected;
};

std::string ReplaceFirst(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(TMeshFileTest, MalformedDocumentsAreRejected) {
  const std::string json =
      *ReadFileToString(testing::RealTMeshPath("hex-me/s04u_tetrahedron.tmesh.json"), 1 << 20);
  const std::vector<JsonCorruption> cases = {
      {"truncated", [](const std::string& s) { return s.substr(0, s.size() / 2); },
       "not a T-mesh JSON document"},
      {"empty", [](const std::string&) { return std::string(); }, "not a T-mesh JSON document"},
      {"not json", [](const std::string&) { return std::string("hello"); },
       "not a T-mesh JSON document"},
      {"wrong type",
       [](const std::string& s) {
         return ReplaceFirst(s, "\"length\":",
                             "\"length\":\"x\","
                             "\"ignored\":");
       },
       "not a T-mesh JSON document"},
      {"id beyond int32",
       [](const std::string& s) {
         return ReplaceFirst(s, "\"from\":", "\"from\":2147483648,\"to2\":");
       },
       "not a T-mesh JSON document"},
      {"unknown key",
       [](const std::string& s) {
         return ReplaceFirst(s, "\"name\":", "\"nmae\":\"x\",\"name\":");
       },
       "not a T-mesh JSON document"},
      {"unknown enum",
       [](const std::string& s) { return ReplaceFirst(s, "\"POS_U\"", "\"SIDEWAYS\""); },
       "not a T-mesh JSON document"},
  };
  for (const JsonCorruption& c : cases) {
    const absl::StatusOr<v1::TMesh> parsed = ParseTMeshJson(c.mutate(json));
    ASSERT_FALSE(parsed.ok()) << c.name << " was accepted";
    EXPECT_EQ(parsed.status().code(), absl::StatusCode::kInvalidArgument) << c.name;
    EXPECT_THAT(std::string(parsed.status().message()), HasSubstr(c.expected)) << c.name;
  }
}

TEST(TMeshFileTest, BinaryAndJsonAgree) {
  const v1::TMesh& json_mesh = Tetrahedron();
  const absl::StatusOr<v1::TMesh> binary = ParseTMeshBinary(json_mesh.SerializeAsString());
  ASSERT_TRUE(binary.ok());
  EXPECT_EQ(binary->SerializeAsString(), json_mesh.SerializeAsString());
  EXPECT_FALSE(ParseTMeshBinary("\xff\xff\xff garbage").ok());
}

TEST(TMeshFileTest, ReadsBothFormatsAndNamesTheFileItCannotParse) {
  const std::filesystem::path dir = TempDir("formats");
  std::filesystem::create_directories(dir);
  const v1::TMesh& mesh = Tetrahedron();
  std::string json;
  ASSERT_TRUE(google::protobuf::util::MessageToJsonString(mesh, &json).ok());
  std::ofstream(dir / "m.tmesh.json") << json;
  std::ofstream(dir / "m.tmesh.pb", std::ios::binary) << mesh.SerializeAsString();
  std::ofstream(dir / "bad.tmesh.pb", std::ios::binary) << "\xff\xff\xff garbage";
  for (const char* name : {"m.tmesh.json", "m.tmesh.pb"}) {
    const absl::StatusOr<TMeshMessage> read = ReadTMeshFile((dir / name).string());
    ASSERT_TRUE(read.ok()) << name << ": " << read.status();
    EXPECT_EQ(read->get().SerializeAsString(), mesh.SerializeAsString()) << name;
  }
  const std::string bad = (dir / "bad.tmesh.pb").string();
  const absl::StatusOr<TMeshMessage> garbage = ReadTMeshFile(bad);
  EXPECT_EQ(garbage.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(garbage.status().message()), HasSubstr(bad));
  std::filesystem::remove_all(dir);
}

TEST(TMeshFileTest, MissingFileIsNotFound) {
  const absl::StatusOr<TMeshMessage> mesh = ReadTMeshFile("/nonexistent/x.tmesh.json");
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(mesh.status().message()), HasSubstr("/nonexistent/x.tmesh.json"));
}

// The extension decides: .pb and .binpb are binary, anything else JSON, whatever the bytes.
TEST(TMeshFileTest, TheFileNamePicksTheFormat) {
  const std::filesystem::path dir = TempDir("names");
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  const absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(spec);
  ASSERT_TRUE(grid.ok()) << grid.status();
  const std::string binary = grid->proto().SerializeAsString();
  const absl::StatusOr<std::string> json = testing::TMeshToJson(grid->proto());
  ASSERT_TRUE(json.ok());
  for (const char* name : {"m.binpb", "m.pb", "m.tmesh.pb"}) {
    std::ofstream(dir / name, std::ios::binary) << binary;
    const absl::StatusOr<TMeshMessage> read = ReadTMeshFile((dir / name).string());
    ASSERT_TRUE(read.ok()) << name << ": " << read.status();
    EXPECT_EQ(read->get().SerializeAsString(), binary) << name;
  }
  for (const char* name : {"m.json", "m.txt", "m"}) {
    std::ofstream(dir / name) << *json;
    const absl::StatusOr<TMeshMessage> read = ReadTMeshFile((dir / name).string());
    ASSERT_TRUE(read.ok()) << name << ": " << read.status();
    EXPECT_EQ(read->get().SerializeAsString(), binary) << name;
  }
  // Binary bytes under a JSON name are not read as binary.
  std::ofstream(dir / "binary.json", std::ios::binary) << binary;
  const std::string misnamed = (dir / "binary.json").string();
  const absl::StatusOr<TMeshMessage> read = ReadTMeshFile(misnamed);
  EXPECT_EQ(read.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(read.status().message()),
              HasSubstr(misnamed + ": not a T-mesh JSON document"));
  std::filesystem::remove_all(dir);
}

TEST(TMeshFileTest, JsonRoundTripsEveryField) {
  const v1::TMesh& mesh = Tetrahedron();
  std::string json;
  ASSERT_TRUE(google::protobuf::util::MessageToJsonString(mesh, &json).ok());
  const absl::StatusOr<v1::TMesh> parsed = ParseTMeshJson(json);
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->SerializeAsString(), mesh.SerializeAsString());
}

// A message made on the mesh's arena takes the mesh by swapping pointers (what the CLI does to
// send a file it read); it lives as long as the TMeshMessage.
TEST(TMeshFileTest, MessagesOnTheMeshArenaTakeTheMeshWithoutACopy) {
  TMeshMessage message;
  *message.mutable_message() = Tetrahedron();
  const v1::Arc* first_arc = &message.get().arcs(0);
  v1::TMesh* other = message.CreateOnArena<v1::TMesh>();
  EXPECT_EQ(other->GetArena(), message.get().GetArena());
  other->Swap(message.mutable_message());
  EXPECT_EQ(&other->arcs(0), first_arc);
  EXPECT_EQ(message.get().arcs_size(), 0);
}

}  // namespace
}  // namespace ispq
