// SPDX-License-Identifier: Apache-2.0
// The model of a T-mesh file (core/proto/tmesh_model_file.h): every real mesh, written as binary
// and as JSON, reads to the model its message decodes to; files that cannot be opened, are too
// large, do not parse or hold an invalid mesh are refused with the path first, as
// core/proto/tmesh_file.h refuses them.
#include "core/proto/tmesh_model_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/proto/tmesh_file.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/core/proto/same_tmesh.h"
#include "tests/support/grid_tmesh_builder.h"
#include "tests/support/test_data.h"

namespace ispq {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// A fresh folder of this process for one test, removed with it.
class Folder {
 public:
  explicit Folder(const std::string& name)
      : dir_(std::filesystem::temp_directory_path() /
             ("ispq-tmesh-model-file-" + std::to_string(::getpid()) + "-" + name)) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  ~Folder() { std::filesystem::remove_all(dir_); }
  std::string Write(const std::string& name, const std::string& bytes) const {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return (dir_ / name).string();
  }

 private:
  std::filesystem::path dir_;
};

TEST(TMeshModelFileTest, EveryRealMeshReadsToTheModelOfItsMessage) {
  const Folder folder("real");
  const std::vector<std::string> files = testing::RealTMeshFiles();
  ASSERT_EQ(files.size(), 62u);
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const v1::TMesh proto = testing::LoadProtoOrDie(file);
    const TMesh whole = testing::TMeshOrDie(proto);
    const std::string binary = folder.Write("m.tmesh.pb", proto.SerializeAsString());
    const absl::StatusOr<TMesh> from_binary = ReadTMeshModelFile(binary);
    ASSERT_TRUE(from_binary.ok()) << from_binary.status();
    testing::ExpectSameTMesh(whole, *from_binary);
    const absl::StatusOr<TMesh> from_json = ReadTMeshModelFile(file);
    ASSERT_TRUE(from_json.ok()) << from_json.status();
    testing::ExpectSameTMesh(whole, *from_json);
  }
}

TEST(TMeshModelFileTest, AMissingFileIsNotFound) {
  for (const char* path : {"/nonexistent/x.tmesh.pb", "/nonexistent/x.tmesh.json"}) {
    const absl::StatusOr<TMesh> mesh = ReadTMeshModelFile(path);
    EXPECT_EQ(mesh.status().code(), absl::StatusCode::kNotFound) << path;
    EXPECT_THAT(std::string(mesh.status().message()), StartsWith(std::string(path) + ": "));
  }
}

// The limit is checked before anything is read: a sparse file of one byte more is refused by its
// size alone.
TEST(TMeshModelFileTest, AFileAboveTheLimitIsRefusedUnread) {
  const Folder folder("large");
  const std::string path = folder.Write("huge.tmesh.pb", "");
  std::filesystem::resize_file(path, kMaxTMeshFileBytes + 1);
  const absl::StatusOr<TMesh> mesh = ReadTMeshModelFile(path);
  EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(mesh.status().message()),
              StartsWith(path + ": file has " + std::to_string(kMaxTMeshFileBytes + 1) + " bytes"));
}

TEST(TMeshModelFileTest, BytesThatDoNotParseAreRefusedNamingTheFile) {
  const Folder folder("garbage");
  const std::string binary = folder.Write("bad.tmesh.pb", "\xff\xff\xff garbage");
  const absl::StatusOr<TMesh> from_binary = ReadTMeshModelFile(binary);
  EXPECT_EQ(from_binary.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(from_binary.status().message()),
              StartsWith(binary + ": the bytes are not a binary T-mesh (ispq.v1.TMesh): "));
  // The message reader words it the same way, so a command refuses such a file alike whether it
  // reads the message or the model.
  EXPECT_THAT(std::string(ReadTMeshFile(binary).status().message()),
              StartsWith(binary + ": the bytes are not a binary T-mesh (ispq.v1.TMesh): "));
  const std::string json = folder.Write("bad.tmesh.json", "{\"nodes\": [");
  const absl::StatusOr<TMesh> from_json = ReadTMeshModelFile(json);
  EXPECT_EQ(from_json.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(from_json.status().message()),
              StartsWith(json + ": not a T-mesh JSON document"));
}

TEST(TMeshModelFileTest, AnInvalidMeshIsRefusedNamingTheFileAndTheElement) {
  const Folder folder("invalid");
  testing::GridTMeshSpec spec;
  spec.blocks = {{{0, 0, 0}, {1, 1, 1}}};
  const absl::StatusOr<testing::GridTMesh> grid = testing::BuildGridTMesh(spec);
  ASSERT_TRUE(grid.ok()) << grid.status();
  v1::TMesh broken = grid->proto();
  broken.mutable_arcs(4)->set_length(-2);
  const absl::StatusOr<std::string> json_text = testing::TMeshToJson(broken);
  ASSERT_TRUE(json_text.ok()) << json_text.status();
  for (const std::string& path : {folder.Write("bad.tmesh.pb", broken.SerializeAsString()),
                                  folder.Write("bad.tmesh.json", *json_text)}) {
    const absl::StatusOr<TMesh> mesh = ReadTMeshModelFile(path);
    EXPECT_EQ(mesh.status().code(), absl::StatusCode::kInvalidArgument) << path;
    EXPECT_THAT(std::string(mesh.status().message()), StartsWith(path + ": arc 4: length -2"));
  }
}

}  // namespace
}  // namespace ispq
