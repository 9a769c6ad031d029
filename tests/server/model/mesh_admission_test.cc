// SPDX-License-Identifier: Apache-2.0
// The door from a client's mesh into the server (server/model/mesh_admission.h): the arc limit
// first, naming --max_arcs; then the core validator, whose message names the offending element;
// the admitted mesh with the statistics jobs report; and its memory reservation, held as long as
// anything holds the mesh and let go when a mesh is refused.
#include "server/model/mesh_admission.h"

#include <memory>
#include <optional>
#include <string>

#include "absl/strings/str_cat.h"
#include "core/mesh_stats.h"
#include "core/proto/mesh_stats_proto.h"
#include "gmock/gmock.h"
#include "google/protobuf/io/zero_copy_stream_impl_lite.h"
#include "gtest/gtest.h"
#include "server/model/mesh_positions.h"
#include "tests/support/test_data.h"

namespace ispq::server {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

v1::TMesh Notch() {
  return testing::LoadProtoOrDie(testing::RealTMeshPath("hex-me/s07c_notch.tmesh.json"));
}

TEST(MeshAdmissionTest, TheArcLimitIsInclusiveAndNamesItsFlag) {
  const v1::TMesh proto = Notch();
  const int arcs = proto.arcs_size();
  EXPECT_TRUE(CheckMeshSize(proto, arcs).ok());
  const absl::Status over = CheckMeshSize(proto, arcs - 1);
  EXPECT_EQ(over.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(over.message()), HasSubstr(absl::StrCat("mesh has ", arcs, " arcs")));
  EXPECT_THAT(std::string(over.message()), HasSubstr("--max_arcs"));
  EXPECT_EQ(AdmitMesh(proto, arcs - 1).status(), over);
}

// An oversized mesh is refused before anything is built from it: its contents do not matter.
TEST(MeshAdmissionTest, AnOversizedMeshIsRefusedForItsSizeBeforeItIsValidated) {
  v1::TMesh garbage;
  for (int i = 0; i < 11; ++i) garbage.add_arcs()->set_length(-1);
  const absl::Status refused = AdmitMesh(garbage, 10).status();
  EXPECT_THAT(std::string(refused.message()), HasSubstr("--max_arcs"));
}

TEST(MeshAdmissionTest, AnInvalidMeshIsRefusedWithTheValidatorsMessage) {
  v1::TMesh proto = Notch();
  proto.mutable_arcs(3)->set_length(-1);
  const absl::Status refused = AdmitMesh(proto, 1000000).status();
  EXPECT_EQ(refused.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(refused.message()), StartsWith("invalid T-mesh: "));
  EXPECT_THAT(std::string(refused.message()), HasSubstr("arc 3"));
}

TEST(MeshAdmissionTest, TheAdmittedMeshCarriesItsStatistics) {
  const v1::TMesh proto = Notch();
  const absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(proto, proto.arcs_size());
  ASSERT_TRUE(admitted.ok()) << admitted.status();
  ASSERT_NE(admitted->mesh, nullptr);
  EXPECT_EQ(admitted->mesh->name(), testing::TMeshOrDie(proto).name());
  EXPECT_EQ(admitted->stats.arcs(), proto.arcs_size());
  EXPECT_EQ(admitted->stats.SerializeAsString(),
            MeshStatsToProto(ComputeMeshStats(*admitted->mesh)).SerializeAsString());
  EXPECT_GT(admitted->stats.subproblems(), 0);
}

// From the bytes of an upload (AdmitMeshBytes, never one parsed message): the same mesh, the same
// statistics and the same node positions as from the message; the arc limit and the validator's
// messages as from the message.
TEST(MeshAdmissionTest, BytesAreAdmittedAsTheMessageIs) {
  const v1::TMesh proto = Notch();
  const std::string bytes = proto.SerializeAsString();
  const TMeshBytesReader read = [&bytes] {
    return std::make_unique<google::protobuf::io::ArrayInputStream>(
        bytes.data(), static_cast<int>(bytes.size()), /*block_size=*/100);
  };
  const absl::StatusOr<AdmittedMesh> from_message = AdmitMesh(proto, proto.arcs_size());
  const absl::StatusOr<AdmittedMesh> from_bytes = AdmitMeshBytes(read, proto.arcs_size());
  ASSERT_TRUE(from_message.ok()) << from_message.status();
  ASSERT_TRUE(from_bytes.ok()) << from_bytes.status();
  EXPECT_EQ(from_bytes->stats.SerializeAsString(), from_message->stats.SerializeAsString());
  const NodePositions* positions = NodePositionsOf(from_bytes->mesh);
  ASSERT_NE(positions, nullptr);
  EXPECT_EQ(*positions, *NodePositionsOf(from_message->mesh));
  EXPECT_EQ(positions->size(), static_cast<size_t>(proto.nodes_size()));

  const absl::Status too_many = AdmitMeshBytes(read, proto.arcs_size() - 1).status();
  EXPECT_EQ(too_many, AdmitMesh(proto, proto.arcs_size() - 1).status());
  v1::TMesh broken = proto;
  broken.mutable_arcs(3)->set_length(-1);
  const std::string broken_bytes = broken.SerializeAsString();
  const absl::Status refused =
      AdmitMeshBytes(
          [&broken_bytes] {
            return std::make_unique<google::protobuf::io::ArrayInputStream>(
                broken_bytes.data(), static_cast<int>(broken_bytes.size()));
          },
          proto.arcs_size())
          .status();
  EXPECT_EQ(refused, AdmitMesh(broken, proto.arcs_size()).status());
}

// The reservation travels in the mesh's shared ownership: a store entry and a job may hold the
// mesh, and the bytes are released when the last of them lets go.
TEST(MeshAdmissionTest, TheMemoryIsReleasedWithTheLastHolderOfTheMesh) {
  MemoryBudget budget(1 << 30);
  std::optional<MemoryReservation> memory = budget.TryReserve(MemoryUse::kJobs, 12345);
  ASSERT_TRUE(memory.has_value());
  absl::StatusOr<AdmittedMesh> admitted = AdmitMesh(Notch(), 1000000, *std::move(memory));
  ASSERT_TRUE(admitted.ok()) << admitted.status();
  std::shared_ptr<const TMesh> job_reference = admitted->mesh;
  admitted->mesh.reset();
  EXPECT_EQ(budget.used(MemoryUse::kJobs), 12345) << "a job still holds the mesh";
  EXPECT_GT(job_reference->num_arcs(), 0);
  job_reference.reset();
  EXPECT_EQ(budget.used(), 0);
}

TEST(MeshAdmissionTest, ARefusedMeshHoldsNoMemory) {
  MemoryBudget budget(1 << 30);
  v1::TMesh invalid = Notch();
  invalid.mutable_arcs(0)->set_length(-1);
  EXPECT_FALSE(AdmitMesh(invalid, 1000000, *budget.TryReserve(MemoryUse::kJobs, 100)).ok());
  EXPECT_FALSE(AdmitMesh(Notch(), 1, *budget.TryReserve(MemoryUse::kJobs, 100)).ok());
  EXPECT_EQ(budget.used(), 0);
}

}  // namespace
}  // namespace ispq::server
