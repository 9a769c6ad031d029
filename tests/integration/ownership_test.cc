// SPDX-License-Identifier: Apache-2.0
// Principals and ownership (issue 7): with several bearer tokens (--auth_tokens_file) or client
// certificates (mutual TLS), every job and stored mesh belongs to the principal that created it.
// Another principal cannot see, watch, cancel or list it, nor delete or use the mesh: it gets
// NOT_FOUND, as for a name that never existed. An admin principal sees and acts on everything.
// Before principals, any holder of the one token could do all of that to everyone's work.
#include <memory>
#include <set>
#include <string>

#include "client/server_connection.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/run_command.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;

std::string TemporaryDirectory() {
  std::string pattern = ::testing::TempDir() + "ispq-owners-XXXXXX";
  EXPECT_NE(mkdtemp(pattern.data()), nullptr);
  return pattern;
}

std::string WriteFile(const std::string& path, const std::string& contents) {
  EXPECT_EQ(RunCommand("printf '" + contents + "' > " + path).exit_code, 0);
  return path;
}

std::set<std::string> ListedJobs(client::QuantizerClient& client) {
  v1::ListJobsRequest list;
  list.set_page_size(1000);
  const absl::StatusOr<v1::ListJobsResponse> page = client.ListJobs(list);
  EXPECT_TRUE(page.ok()) << page.status();
  std::set<std::string> names;
  if (page.ok()) {
    for (const v1::Job& job : page->jobs()) names.insert(job.name());
  }
  return names;
}

class OwnershipTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string tokens =
        WriteFile(TemporaryDirectory() + "/tokens",
                  "# principal token\\nalice alice-secret\\nbob bob-secret\\n\\n"
                  "ops ops-secret\\n");
    server_ = StartServerOrFail({"--auth_tokens_file=" + tokens, "--admin_principals=ops"});
    ASSERT_NE(server_, nullptr);
    alice_ = std::make_unique<client::QuantizerClient>(ClientOf(*server_, "alice-secret"));
    bob_ = std::make_unique<client::QuantizerClient>(ClientOf(*server_, "bob-secret"));
    ops_ = std::make_unique<client::QuantizerClient>(ClientOf(*server_, "ops-secret"));
  }

  std::unique_ptr<ServerProcess> server_;
  std::unique_ptr<client::QuantizerClient> alice_;
  std::unique_ptr<client::QuantizerClient> bob_;
  std::unique_ptr<client::QuantizerClient> ops_;
};

TEST_F(OwnershipTest, JobsAreVisibleOnlyToTheirOwnerAndAdmins) {
  const absl::StatusOr<v1::Job> job = alice_->SubmitJob(RequestFor(NotchMesh(), 100));
  ASSERT_TRUE(job.ok()) << job.status();
  EXPECT_EQ(job->owner(), "alice");
  const absl::StatusOr<v1::Job> done = WaitUntilDone(*alice_, job->name());
  ASSERT_TRUE(done.ok()) << done.status();
  EXPECT_TRUE(IsValidResult(NotchMesh(), done->result()));

  EXPECT_EQ(bob_->GetJob(job->name()).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(bob_->CancelJob(job->name()).status().code(), absl::StatusCode::kNotFound);
  const client::JobOutcome watched = bob_->WatchJob(job->name(), 0, StreamFor(absl::Seconds(30)));
  EXPECT_EQ(watched.status.code(), absl::StatusCode::kNotFound);
  EXPECT_FALSE(watched.result.has_value());
  EXPECT_TRUE(ListedJobs(*bob_).empty());

  const client::JobOutcome own =
      bob_->Quantize(RequestFor(NotchMesh(), 50), StreamFor(kJobTimeout));
  ASSERT_TRUE(own.status.ok()) << own.status;
  EXPECT_TRUE(IsValidResult(NotchMesh(), *own.result));
  EXPECT_EQ(ListedJobs(*alice_), std::set<std::string>{job->name()});
  EXPECT_EQ(ListedJobs(*bob_), std::set<std::string>{own.job});
  EXPECT_EQ(ListedJobs(*ops_), (std::set<std::string>{job->name(), own.job}));
  const absl::StatusOr<v1::Job> seen_by_admin = ops_->GetJob(job->name());
  ASSERT_TRUE(seen_by_admin.ok()) << seen_by_admin.status();
  EXPECT_EQ(seen_by_admin->owner(), "alice");
}

TEST_F(OwnershipTest, OnlyTheOwnerOrAnAdminCancelsAJob) {
  const absl::StatusOr<v1::Mesh> stored = alice_->CreateMesh(LongRunningMesh());
  ASSERT_TRUE(stored.ok()) << stored.status();
  const absl::StatusOr<v1::Job> job = alice_->SubmitJob(StoredMeshRequest(stored->name(), 100));
  ASSERT_TRUE(job.ok()) << job.status();
  ASSERT_TRUE(WaitForState(*alice_, job->name(), v1::RUNNING).ok());
  EXPECT_EQ(bob_->CancelJob(job->name()).status().code(), absl::StatusCode::kNotFound);
  const absl::StatusOr<v1::Job> still = alice_->GetJob(job->name(), v1::BASIC);
  ASSERT_TRUE(still.ok());
  EXPECT_EQ(still->state(), v1::RUNNING) << "bob's cancel changed nothing";
  const absl::StatusOr<v1::Job> cancelled = ops_->CancelJob(job->name());
  ASSERT_TRUE(cancelled.ok()) << cancelled.status();
  const absl::StatusOr<v1::Job> done = WaitUntilDone(*alice_, job->name());
  ASSERT_TRUE(done.ok()) << done.status();
  EXPECT_EQ(done->state(), v1::CANCELLED);
  if (done->has_result() && done->result().valid()) {
    EXPECT_TRUE(IsValidResult(LongRunningMesh(), done->result()));
  }
}

TEST_F(OwnershipTest, StoredMeshesAreUsableAndDeletableOnlyByTheirOwner) {
  const absl::StatusOr<v1::Mesh> stored = alice_->CreateMesh(NotchMesh());
  ASSERT_TRUE(stored.ok()) << stored.status();
  EXPECT_EQ(stored->owner(), "alice");
  EXPECT_EQ(bob_->GetMesh(stored->name()).status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(bob_->DeleteMesh(stored->name()).code(), absl::StatusCode::kNotFound);
  const absl::StatusOr<v1::Job> borrowed = bob_->SubmitJob(StoredMeshRequest(stored->name(), 100));
  EXPECT_EQ(borrowed.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(borrowed.status().message()), HasSubstr("not found"));

  const client::JobOutcome own =
      alice_->Quantize(StoredMeshRequest(stored->name(), 100), StreamFor(kJobTimeout));
  ASSERT_TRUE(own.status.ok()) << own.status;
  EXPECT_TRUE(IsValidResult(NotchMesh(), *own.result));
  ASSERT_TRUE(ops_->GetMesh(stored->name()).ok());
  ASSERT_TRUE(alice_->DeleteMesh(stored->name()).ok());
  EXPECT_EQ(alice_->GetMesh(stored->name()).status().code(), absl::StatusCode::kNotFound);
}

TEST_F(OwnershipTest, UnknownTokensAreRefused) {
  client::QuantizerClient stranger = ClientOf(*server_, "not-a-token");
  EXPECT_EQ(stranger.GetServerStats().status().code(), absl::StatusCode::kUnauthenticated);
  client::QuantizerClient anonymous = ClientOf(*server_);
  EXPECT_EQ(anonymous.SubmitJob(RequestFor(NotchMesh(), 100)).status().code(),
            absl::StatusCode::kUnauthenticated);
}

TEST(OwnershipConfigTest, TheSingleTokenIsOnePrincipalNamedDefault) {
  const std::string token = WriteFile(TemporaryDirectory() + "/token", "only-secret\\n");
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--auth_token_file=" + token});
  ASSERT_NE(server, nullptr);
  client::QuantizerClient client = ClientOf(*server, "only-secret");
  const client::JobOutcome outcome =
      client.Quantize(RequestFor(NotchMesh(), 100), StreamFor(kJobTimeout));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  EXPECT_TRUE(IsValidResult(NotchMesh(), *outcome.result));
  const absl::StatusOr<v1::Job> job = client.GetJob(outcome.job);
  ASSERT_TRUE(job.ok()) << job.status();
  EXPECT_EQ(job->owner(), "default");
}

TEST(OwnershipConfigTest, MalformedTokenFilesStopTheServerAtStart) {
  const std::string directory = TemporaryDirectory();
  const std::string malformed = WriteFile(directory + "/malformed", "alice a-token\\nbob\\n");
  const absl::StatusOr<std::unique_ptr<ServerProcess>> refused =
      ServerProcess::Start(ServerBinaryPath(), {"--auth_tokens_file=" + malformed});
  ASSERT_FALSE(refused.ok());
  EXPECT_THAT(std::string(refused.status().message()),
              HasSubstr("line 2: expected 'PRINCIPAL TOKEN'"));
  const std::string duplicate = WriteFile(directory + "/duplicate", "alice same\\nbob same\\n");
  const absl::StatusOr<std::unique_ptr<ServerProcess>> twice =
      ServerProcess::Start(ServerBinaryPath(), {"--auth_tokens_file=" + duplicate});
  ASSERT_FALSE(twice.ok());
  EXPECT_THAT(std::string(twice.status().message()),
              HasSubstr("line 2: the token is already used"));
  const absl::StatusOr<std::unique_ptr<ServerProcess>> both = ServerProcess::Start(
      ServerBinaryPath(), {"--auth_tokens_file=" + duplicate, "--auth_token=x"});
  ASSERT_FALSE(both.ok());
  EXPECT_THAT(std::string(both.status().message()), HasSubstr("excludes --auth_token"));
}

// Mutual TLS: the verified client certificate's subject is the principal.
struct Certificate {
  std::string cert_file;
  std::string key_file;
};

// A certificate for `common_name` signed by the CA in `directory` (made on first use).
Certificate SignedCertificate(const std::string& directory, const std::string& common_name) {
  const std::string ca = directory + "/ca";
  if (RunCommand("test -f " + ca + ".crt").exit_code != 0) {
    const CommandResult made =
        RunCommand("openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=test-ca -keyout " +
                   ca + ".key -out " + ca + ".crt 2>&1");
    EXPECT_EQ(made.exit_code, 0) << made.output;
  }
  const std::string base = directory + "/" + common_name;
  const CommandResult made = RunCommand(
      "openssl req -newkey rsa:2048 -nodes -subj '/O=Example/CN=" + common_name + "' -addext " +
      "subjectAltName=DNS:localhost,IP:127.0.0.1 -keyout " + base + ".key -out " + base +
      ".csr 2>&1 && openssl x509 -req -in " + base + ".csr -CA " + ca + ".crt -CAkey " + ca +
      ".key -CAcreateserial -days 2 -copy_extensions copy -out " + base + ".crt 2>&1");
  EXPECT_EQ(made.exit_code, 0) << made.output;
  return {base + ".crt", base + ".key"};
}

TEST(OwnershipTlsTest, ClientCertificateSubjectsArePrincipals) {
  const std::string directory = TemporaryDirectory();
  const Certificate server_certificate = SignedCertificate(directory, "localhost");
  const Certificate carol = SignedCertificate(directory, "carol");
  const Certificate dave = SignedCertificate(directory, "dave");
  std::unique_ptr<ServerProcess> server = StartServerOrFail(
      {"--tls_cert=" + server_certificate.cert_file, "--tls_key=" + server_certificate.key_file,
       "--tls_client_ca=" + directory + "/ca.crt"});
  ASSERT_NE(server, nullptr);
  const auto connect = [&](const Certificate& certificate) {
    client::ServerConnection connection;
    connection.address = "localhost:" + std::to_string(server->port());
    connection.tls_ca_file = directory + "/ca.crt";
    connection.tls_cert_file = certificate.cert_file;
    connection.tls_key_file = certificate.key_file;
    absl::StatusOr<client::QuantizerClient> client = client::QuantizerClient::Connect(connection);
    EXPECT_TRUE(client.ok()) << client.status();
    return *std::move(client);
  };
  client::QuantizerClient as_carol = connect(carol);
  client::QuantizerClient as_dave = connect(dave);
  const client::JobOutcome outcome =
      as_carol.Quantize(RequestFor(NotchMesh(), 100), StreamFor(kJobTimeout));
  ASSERT_TRUE(outcome.status.ok()) << outcome.status;
  EXPECT_TRUE(IsValidResult(NotchMesh(), *outcome.result));
  const absl::StatusOr<v1::Job> job = as_carol.GetJob(outcome.job);
  ASSERT_TRUE(job.ok()) << job.status();
  EXPECT_EQ(job->owner(), "CN=carol,O=Example");
  EXPECT_EQ(as_dave.GetJob(outcome.job).status().code(), absl::StatusCode::kNotFound);
  EXPECT_TRUE(ListedJobs(as_dave).empty());
}

}  // namespace
}  // namespace ispq::testing
