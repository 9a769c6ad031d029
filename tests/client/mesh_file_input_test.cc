// SPDX-License-Identifier: Apache-2.0
// LoadMeshFile and LoadMeshModel: a valid file in either format gives the message as read (the
// former) and the validated model (both); a file that does not parse and a mesh that fails
// validation are both refused with a message that starts with the file's path (and names the
// element for the latter), the same from both.
#include "client/mesh_file_input.h"

#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/client/client_test_files.h"
#include "tests/support/grid_tmesh_builder.h"

namespace ispq::cli {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

TEST(MeshFileInputTest, AValidFileGivesTheMessageAndTheModel) {
  const testing::TestFolder folder;
  const std::string json =
      folder.Write("m.tmesh.json", *testing::TMeshToJson(testing::TwoBlockMesh()));
  const std::string binary =
      folder.Write("m.tmesh.pb", testing::TwoBlockMesh().SerializeAsString());
  for (const std::string& path : {json, binary}) {
    const absl::StatusOr<MeshFile> file = LoadMeshFile(path);
    ASSERT_TRUE(file.ok()) << file.status();
    EXPECT_EQ(file->proto.get().SerializeAsString(), testing::TwoBlockMesh().SerializeAsString());
    EXPECT_EQ(file->mesh.num_arcs(), testing::TwoBlockMesh().arcs_size());
    EXPECT_EQ(file->mesh.num_blocks(), 2);
    const absl::StatusOr<TMesh> model = LoadMeshModel(path);
    ASSERT_TRUE(model.ok()) << model.status();
    EXPECT_EQ(model->num_arcs(), testing::TwoBlockMesh().arcs_size());
    EXPECT_EQ(model->num_blocks(), 2);
  }
}

TEST(MeshFileInputTest, AFileThatDoesNotParseIsNamed) {
  const testing::TestFolder folder;
  const std::string path = folder.Write("broken.tmesh.json", "{\"nodes\": [");
  const absl::StatusOr<MeshFile> file = LoadMeshFile(path);
  EXPECT_EQ(file.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(file.status().message()), StartsWith(path + ": "));
  EXPECT_EQ(LoadMeshModel(path).status(), file.status());
  EXPECT_EQ(LoadMeshFile(folder.Path("missing.json")).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(LoadMeshModel(folder.Path("missing.pb")).status().code(), absl::StatusCode::kNotFound);
}

TEST(MeshFileInputTest, AMeshThatFailsValidationIsNamedWithItsElement) {
  const testing::TestFolder folder;
  v1::TMesh broken = testing::TwoBlockMesh();
  broken.mutable_arcs(4)->set_length(-2);
  const std::string path = folder.Write("bad.tmesh.pb", broken.SerializeAsString());
  const absl::StatusOr<MeshFile> file = LoadMeshFile(path);
  EXPECT_EQ(file.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(file.status().message()), StartsWith(path + ": arc 4: length -2"));
  EXPECT_EQ(LoadMeshModel(path).status(), file.status());
}

}  // namespace
}  // namespace ispq::cli
