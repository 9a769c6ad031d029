// SPDX-License-Identifier: Apache-2.0
// UploadMesh (server/grpc/mesh_upload.h) against the real server: a mesh larger than the server's
// message limit arrives in chunks, is stored and quantized like any stored mesh (valid, equal to
// the in-process answer), also from the CLI, which uploads large meshes by itself; the declared
// size is reserved before any chunk and released however the upload ends (completed, refused,
// stalled and dropped by the watchdog); sizes that disagree with the declaration, bytes that are
// no T-mesh and meshes the validator refuses are INVALID_ARGUMENT naming what is wrong.
#include <fstream>
#include <iterator>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/proto/quantization_proto.h"
#include "core/quantizer.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "ispq/v1/service.grpc.pb.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;

constexpr int kMessageLimit = 4 << 20;  // the server's --max_message_bytes in these tests

class MeshUploadTest : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ = StartServerOrFail({absl::StrCat("--max_message_bytes=", kMessageLimit),
                                 "--upload_idle_seconds=1", "--max_upload_bytes=100000000"});
    ASSERT_NE(server_, nullptr);
  }

  client::QuantizerClient Client() { return ClientOf(*server_); }

  // An upload written by hand: `messages` as given, then the stream closed. The call's status.
  grpc::Status RawUpload(const std::vector<v1::UploadMeshRequest>& messages, v1::Mesh* answer) {
    std::unique_ptr<v1::Quantizer::Stub> stub = v1::Quantizer::NewStub(Client().channel());
    grpc::ClientContext context;
    context.set_deadline(absl::ToChronoTime(absl::Now() + kJobTimeout));
    auto writer = stub->UploadMesh(&context, answer);
    for (const v1::UploadMeshRequest& message : messages) {
      if (!writer->Write(message)) break;
    }
    writer->WritesDone();
    return writer->Finish();
  }

  // Waits until nothing is held for requests any more (bounded by the job timeout).
  void ExpectRequestMemoryReleased() {
    client::QuantizerClient client = Client();
    const absl::Time deadline = absl::Now() + kJobTimeout;
    int64_t held = -1;
    while (absl::Now() < deadline) {
      absl::StatusOr<v1::ServerStats> stats = client.GetServerStats();
      ASSERT_TRUE(stats.ok()) << stats.status();
      held = stats->memory().requests_bytes();
      if (held < 1024) return;  // only the stats request itself
      absl::SleepFor(absl::Milliseconds(20));
    }
    FAIL() << held << " bytes still held for requests";
  }

  std::unique_ptr<ServerProcess> server_;
};

// The q of a result file, as text.
std::string ResultQ(const std::string& path) {
  std::ifstream in(path);
  const std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  v1::QuantizationResult result;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(json, &result).ok()) << path;
  return absl::StrJoin(result.q(), ",");
}

std::vector<v1::UploadMeshRequest> Chunks(const std::string& bytes, int64_t declared,
                                          size_t chunk = 1 << 20) {
  std::vector<v1::UploadMeshRequest> messages;
  for (size_t offset = 0; offset < bytes.size() || messages.empty(); offset += chunk) {
    messages.emplace_back();
    if (offset == 0) messages.back().set_total_bytes(declared);
    messages.back().set_chunk(bytes.substr(offset, chunk));
  }
  return messages;
}

TEST_F(MeshUploadTest, AMeshAboveTheMessageLimitIsUploadedStoredAndQuantized) {
  const v1::TMesh mesh = FemurCopies(120);  // about 7 MB
  ASSERT_GT(mesh.ByteSizeLong(), static_cast<size_t>(kMessageLimit));
  client::QuantizerClient client = Client();
  const absl::StatusOr<v1::Mesh> refused = client.CreateMesh(mesh);
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kResourceExhausted) << refused.status();

  const absl::StatusOr<v1::Mesh> stored = client.UploadMesh(mesh);
  ASSERT_TRUE(stored.ok()) << stored.status();
  EXPECT_EQ(stored->mesh_stats().arcs(), mesh.arcs_size());
  ASSERT_NO_FATAL_FAILURE(ExpectRequestMemoryReleased());

  const client::JobOutcome outcome =
      client.Quantize(StoredMeshRequest(stored->name(), 5), StreamFor(kJobTimeout));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  ASSERT_TRUE(IsValidResult(mesh, *outcome.result));
  const TMesh model = TMeshOrDie(mesh);
  v1::QuantizationOptions options;
  options.mutable_scaling()->set_level_percent(5);
  absl::StatusOr<QuantizeResult> local = Quantize(model, *QuantizeOptionsFromProto(options, model));
  ASSERT_TRUE(local.ok()) << local.status();
  EXPECT_EQ(absl::StrJoin(outcome.result->q(), ","), absl::StrJoin(local->q, ","));
}

TEST_F(MeshUploadTest, TheCommandLineUploadsALargeMeshByItselfAndDeletesItAfterwards) {
  const std::string path = ::testing::TempDir() + "femur-copies.tmesh.pb";
  {
    std::ofstream out(path, std::ios::binary);
    ASSERT_TRUE(FemurCopies(75).SerializeToOstream(&out));
  }
  const std::string cli = std::string(ISPQ_CLI_PATH);
  const CommandResult remote =
      RunCommand(absl::StrCat(cli, " quantize ", path, " --server ", server_->address(),
                              " --level 5 --out ", path, ".remote.json --progress=true"));
  ASSERT_EQ(remote.exit_code, 0) << remote.output;
  EXPECT_THAT(remote.output, HasSubstr("uploading the mesh"));
  const CommandResult local = RunCommand(absl::StrCat(
      cli, " quantize ", path, " --local --level 5 --out ", path, ".local.json --progress=false"));
  ASSERT_EQ(local.exit_code, 0) << local.output;
  const CommandResult validated = RunCommand(
      absl::StrCat(cli, " validate ", path, " --result ", path, ".remote.json --level 5"));
  EXPECT_EQ(validated.exit_code, 0) << validated.output;
  EXPECT_EQ(ResultQ(path + ".remote.json"), ResultQ(path + ".local.json"));
  absl::StatusOr<v1::ServerStats> stats = Client().GetServerStats();
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats->stored_meshes(), 0) << "the CLI deletes the mesh it uploaded";
}

TEST_F(MeshUploadTest, AStalledUploadIsDroppedAndItsMemoryReleased) {
  std::unique_ptr<v1::Quantizer::Stub> stub = v1::Quantizer::NewStub(Client().channel());
  grpc::ClientContext context;
  context.set_deadline(absl::ToChronoTime(absl::Now() + kJobTimeout));
  v1::Mesh answer;
  auto writer = stub->UploadMesh(&context, &answer);
  v1::UploadMeshRequest first;
  first.set_total_bytes(50'000'000);
  first.set_chunk(std::string(1 << 20, 'x'));
  ASSERT_TRUE(writer->Write(first));
  // Nothing more is sent; the server drops the upload after its idle limit (1 s).
  const grpc::Status status = writer->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::CANCELLED) << status.error_message();
  ASSERT_NO_FATAL_FAILURE(ExpectRequestMemoryReleased());
  EXPECT_TRUE(server_->WaitForLog("event=upload_dropped reason=idle"));
}

TEST_F(MeshUploadTest, SizesThatDisagreeWithTheDeclarationAreRefused) {
  const std::string bytes = FemurCopies(2).SerializeAsString();
  v1::Mesh answer;
  grpc::Status status = RawUpload(Chunks(bytes, bytes.size() + 10), &answer);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr(absl::StrCat("ended after ", bytes.size(),
                                                             " bytes of the ", bytes.size() + 10)));
  status = RawUpload(Chunks(bytes, bytes.size() - 10), &answer);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("more than the"));
  status = RawUpload(Chunks(bytes, 0), &answer);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("total_bytes must be > 0"));
  status = RawUpload(Chunks("x", 200'000'000), &answer);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("--max_upload_bytes"));
  ASSERT_NO_FATAL_FAILURE(ExpectRequestMemoryReleased());
}

TEST_F(MeshUploadTest, AnUploadLargerThanTheMemoryBudgetIsRefusedBeforeAnyChunk) {
  std::unique_ptr<ServerProcess> small =
      StartServerOrFail({"--max_memory_bytes=64MiB", "--max_upload_bytes=1000000000"});
  ASSERT_NE(small, nullptr);
  std::unique_ptr<v1::Quantizer::Stub> stub = v1::Quantizer::NewStub(ClientOf(*small).channel());
  grpc::ClientContext context;
  v1::Mesh answer;
  auto writer = stub->UploadMesh(&context, &answer);
  v1::UploadMeshRequest first;
  first.set_total_bytes(500'000'000);
  writer->Write(first);
  writer->WritesDone();
  const grpc::Status status = writer->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
}

TEST_F(MeshUploadTest, BytesThatAreNoValidMeshAreNamed) {
  v1::Mesh answer;
  const std::string garbage(1000, '\xff');
  grpc::Status status = RawUpload(Chunks(garbage, garbage.size()), &answer);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();

  v1::TMesh broken = FemurCopies(1);
  broken.mutable_arcs(5)->set_length(-1);
  const std::string bytes = broken.SerializeAsString();
  status = RawUpload(Chunks(bytes, bytes.size(), 1000), &answer);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("arc 5"));
  ASSERT_NO_FATAL_FAILURE(ExpectRequestMemoryReleased());
}

// The arc count is checked on the uploaded bytes before any element is decoded.
TEST(MeshUploadLimitsTest, AnUploadAboveMaxArcsIsRefusedNamingTheFlag) {
  const v1::TMesh mesh = FemurCopies(2);
  std::unique_ptr<ServerProcess> server =
      StartServerOrFail({absl::StrCat("--max_arcs=", mesh.arcs_size() - 1)});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server);
  const absl::StatusOr<v1::Mesh> refused = client.UploadMesh(mesh, /*chunk_bytes=*/4096);
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument) << refused.status();
  EXPECT_THAT(std::string(refused.status().message()),
              HasSubstr(absl::StrCat("mesh has ", mesh.arcs_size(), " arcs")));
  EXPECT_THAT(std::string(refused.status().message()), HasSubstr("--max_arcs"));
}

TEST(MeshUploadAuthTest, AnUploadWithoutTheTokenIsRefused) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--auth_token=upload-secret"});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient anonymous = ClientOf(*server);
  EXPECT_EQ(anonymous.UploadMesh(FemurCopies(1)).status().code(),
            absl::StatusCode::kUnauthenticated);
  client::QuantizerClient client = ClientOf(*server, "upload-secret");
  const absl::StatusOr<v1::Mesh> stored = client.UploadMesh(FemurCopies(1));
  ASSERT_TRUE(stored.ok()) << stored.status();
}

}  // namespace
}  // namespace ispq::testing
