// SPDX-License-Identifier: Apache-2.0
#include "tests/integration/service_test_support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/time/clock.h"
#include "client/server_connection.h"
#include "core/proto/quantization_proto.h"
#include "core/proto/tmesh_from_proto.h"
#include "core/quantization_validator.h"
#include "core/quantizer.h"
#include "tests/support/test_data.h"
#include "tests/support/tmesh_copies.h"

namespace ispq::testing {
namespace {

constexpr char kLongRunningModel[] =
    "2017_-_Explicit_Cylindrical_Maps_for_General_Tubular_Shapes_femur_shell1";
constexpr double kLongRunningSeconds = 60;
constexpr int kMaxCopies = 400;  // about 120k arcs, 24 MB: inside the default message limit

}  // namespace

client::StreamOptions StreamFor(absl::Duration timeout, client::EventHandler on_event) {
  client::StreamOptions options;
  options.on_event = std::move(on_event);
  options.timeout = timeout;
  return options;
}

std::unique_ptr<ServerProcess> StartServerOrFail(const std::vector<std::string>& flags) {
  absl::StatusOr<std::unique_ptr<ServerProcess>> server =
      ServerProcess::Start(ServerBinaryPath(), flags);
  if (!server.ok()) {
    ADD_FAILURE() << "cannot start ispq-server: " << server.status();
    return nullptr;
  }
  return *std::move(server);
}

client::QuantizerClient ClientOf(const ServerProcess& server, const std::string& auth_token) {
  client::ServerConnection connection;
  connection.address = server.address();
  connection.auth_token = auth_token;
  absl::StatusOr<client::QuantizerClient> client = client::QuantizerClient::Connect(connection);
  EXPECT_TRUE(client.ok()) << client.status();
  return *std::move(client);
}

v1::QuantizeRequest RequestFor(const v1::TMesh& mesh, int level_percent) {
  v1::QuantizeRequest request;
  *request.mutable_mesh() = mesh;
  request.mutable_options()->mutable_scaling()->set_level_percent(level_percent);
  return request;
}

v1::QuantizeRequest StoredMeshRequest(const std::string& stored_mesh, int level_percent) {
  v1::QuantizeRequest request;
  request.set_stored_mesh(stored_mesh);
  request.mutable_options()->mutable_scaling()->set_level_percent(level_percent);
  return request;
}

const v1::TMesh& NotchMesh() {
  static const v1::TMesh* mesh =
      new v1::TMesh(LoadProtoOrDie(RealTMeshPath("hex-me/s07c_notch.tmesh.json")));
  return *mesh;
}

v1::TMesh RealMeshNamed(const std::string& model) {
  for (const std::string& path : RealTMeshFiles()) {
    if (ShortName(path).ends_with("/" + model)) return LoadProtoOrDie(path);
  }
  ADD_FAILURE() << "no real T-mesh named " << model << " in " << RealTMeshDir();
  return v1::TMesh();
}

namespace {

// One copy of the base mesh and its in-process solve time at level 100.
struct Calibration {
  v1::TMesh base;
  double seconds = 0;
};

const Calibration& BaseCalibration() {
  static const Calibration* calibration = [] {
    auto* result = new Calibration;
    result->base = RealMeshNamed(kLongRunningModel);
    const TMesh core_mesh = TMeshOrDie(result->base);
    v1::QuantizationOptions options;
    options.mutable_scaling()->set_level_percent(100);
    const absl::StatusOr<QuantizeOptions> resolved = QuantizeOptionsFromProto(options, core_mesh);
    const auto start = std::chrono::steady_clock::now();
    const absl::StatusOr<QuantizeResult> solved = Quantize(core_mesh, *resolved);
    result->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_TRUE(solved.ok() && solved->valid) << "the calibration solve failed";
    return result;
  }();
  return *calibration;
}

}  // namespace

v1::TMesh MeshTakingSeconds(double seconds) {
  const Calibration& calibration = BaseCalibration();
  const int copies = std::clamp(
      static_cast<int>(std::ceil(seconds / std::max(calibration.seconds, 1e-3))), 1, kMaxCopies);
  return DisjointCopies(calibration.base, copies);
}

v1::TMesh FemurCopies(int copies) { return DisjointCopies(BaseCalibration().base, copies); }

const v1::TMesh& LargeMesh() {
  static const v1::TMesh* mesh = new v1::TMesh(FemurCopies(kMaxCopies));
  return *mesh;
}

const v1::TMesh& LongRunningMesh() {
  static const v1::TMesh* mesh = new v1::TMesh(MeshTakingSeconds(kLongRunningSeconds));
  return *mesh;
}

::testing::AssertionResult IsValidResult(const v1::TMesh& mesh_proto,
                                         const v1::QuantizationResult& result) {
  const absl::StatusOr<TMesh> mesh = TMeshFromProto(mesh_proto);
  if (!mesh.ok()) return ::testing::AssertionFailure() << "invalid mesh: " << mesh.status();
  const absl::StatusOr<std::vector<int64_t>> q = QuantizationFromProto(result, *mesh);
  if (!q.ok()) return ::testing::AssertionFailure() << q.status();
  const absl::StatusOr<ValidationReport> report = ValidateQuantization(*mesh, *q);
  if (!report.ok()) return ::testing::AssertionFailure() << report.status();
  if (!report->valid()) {
    return ::testing::AssertionFailure() << "the validator rejects q:\n" << report->Describe();
  }
  if (!result.valid()) {
    return ::testing::AssertionFailure() << "the validator accepts q but the result says invalid";
  }
  return ::testing::AssertionSuccess();
}

absl::StatusOr<v1::Job> WaitUntilDone(client::QuantizerClient& client, const std::string& job,
                                      absl::Duration timeout) {
  const absl::Time deadline = absl::Now() + timeout;
  while (true) {
    absl::StatusOr<v1::Job> got = client.GetJob(job);
    if (!got.ok() || got->done()) return got;
    if (absl::Now() > deadline) {
      return absl::DeadlineExceededError(absl::StrCat(job, " still ",
                                                      v1::JobState_Name(got->state()), " after ",
                                                      absl::FormatDuration(timeout)));
    }
    absl::SleepFor(absl::Milliseconds(20));
  }
}

absl::Status WaitForState(client::QuantizerClient& client, const std::string& job,
                          v1::JobState state, absl::Duration timeout) {
  const absl::Time deadline = absl::Now() + timeout;
  while (true) {
    absl::StatusOr<v1::Job> got = client.GetJob(job, v1::BASIC);
    if (!got.ok()) return got.status();
    if (got->state() == state) return absl::OkStatus();
    if (got->done() || absl::Now() > deadline) {
      return absl::FailedPreconditionError(absl::StrCat(
          job, " is ", v1::JobState_Name(got->state()), ", waited for ", v1::JobState_Name(state)));
    }
    absl::SleepFor(absl::Milliseconds(20));
  }
}

}  // namespace ispq::testing
