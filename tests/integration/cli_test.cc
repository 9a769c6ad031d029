// SPDX-License-Identifier: Apache-2.0
// The `ispq` command line against a real server, as a script would run it: the remote
// quantize path writes the same result as the local one, the job subcommands (submit, watch,
// cancel, jobs), health and server-stats, plain progress lines when not on a TTY, and the exit
// codes scripts rely on (client/exit_codes.h).
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/run_command.h"
#include "tests/support/test_data.h"

namespace ispq::testing {
namespace {

using ::testing::HasSubstr;
using ::testing::MatchesRegex;

std::string Ispq(const std::string& args) { return std::string(ISPQ_CLI_PATH) + " " + args; }

std::string TempPath(const std::string& name) { return ::testing::TempDir() + name; }

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream contents;
  contents << in.rdbuf();
  return contents.str();
}

v1::QuantizationResult ParseResult(const std::string& json) {
  v1::QuantizationResult result;
  google::protobuf::util::JsonParseOptions options;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(json, &result, options).ok()) << json;
  return result;
}

// The result without the timings, which differ from run to run.
v1::QuantizationResult WithoutTimings(v1::QuantizationResult result) {
  v1::QuantizationStats* stats = result.mutable_stats();
  stats->clear_greedy_seconds();
  stats->clear_separation_search_seconds();
  stats->clear_separating_update_seconds();
  stats->clear_solve_seconds();
  stats->clear_lower_bound_seconds();
  stats->clear_exact_seconds();
  stats->clear_layers_seconds();
  return result;
}

// A T-mesh file of disjoint copies that takes minutes: long enough to hold a worker.
std::string LongRunningMeshFile() {
  const std::string path = TempPath("long_running.tmesh.pb");
  std::ofstream(path, std::ios::binary) << LongRunningMesh().SerializeAsString();
  return path;
}

class CliTest : public ::testing::Test {
 protected:
  void StartServer(const std::vector<std::string>& flags) {
    server_ = StartServerOrFail(flags);
    ASSERT_NE(server_, nullptr);
    server_flag_ = " --server " + server_->address();
  }

  std::unique_ptr<ServerProcess> server_;
  std::string server_flag_;
};

TEST_F(CliTest, RemoteQuantizeWritesTheSameResultAsLocal) {
  ASSERT_NO_FATAL_FAILURE(StartServer({}));
  const std::string mesh = RealTMeshPath("hex-me/s07c_notch.tmesh.json");
  const std::string remote_file = TempPath("remote.json");
  const std::string local_file = TempPath("local.json");
  const CommandResult remote =
      RunCommand(Ispq("quantize " + mesh + server_flag_ + " --level 50 --out " + remote_file));
  ASSERT_EQ(remote.exit_code, 0) << remote.output;
  EXPECT_THAT(remote.output, HasSubstr("accepted: s07c_notch, 75 arcs"));
  EXPECT_THAT(remote.output, HasSubstr("progress phase="));  // plain lines: not a TTY
  EXPECT_THAT(remote.output, HasSubstr("valid quantization of s07c_notch"));
  const CommandResult local = RunCommand(
      Ispq("quantize " + mesh + " --local --level 50 --progress=false --out " + local_file));
  ASSERT_EQ(local.exit_code, 0) << local.output;

  const v1::QuantizationResult from_server = ParseResult(ReadFile(remote_file));
  const v1::QuantizationResult in_process = ParseResult(ReadFile(local_file));
  EXPECT_EQ(WithoutTimings(from_server).SerializeAsString(),
            WithoutTimings(in_process).SerializeAsString());
  EXPECT_TRUE(IsValidResult(NotchMesh(), from_server));

  // --json puts the same document on stdout.
  const CommandResult json =
      RunCommand(Ispq("quantize " + mesh + server_flag_ + " --level 50 --json --progress=false"));
  ASSERT_EQ(json.exit_code, 0) << json.output;
  EXPECT_EQ(WithoutTimings(ParseResult(json.output)).SerializeAsString(),
            WithoutTimings(in_process).SerializeAsString());
}

TEST_F(CliTest, SubmitWatchJobsCancelHealthAndStats) {
  ASSERT_NO_FATAL_FAILURE(StartServer({}));
  const std::string mesh = RealTMeshPath("singularity-constrained-fields/fanpart.tmesh.json");
  const CommandResult submitted = RunCommand(Ispq("submit " + mesh + server_flag_ + " --level 10"));
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;
  const std::string job(absl::StripAsciiWhitespace(submitted.output));
  EXPECT_THAT(job, MatchesRegex("jobs/[0-9a-f]{16}"));

  const std::string result_file = TempPath("watched.json");
  const CommandResult watched =
      RunCommand(Ispq("watch " + job + server_flag_ + " --out " + result_file));
  ASSERT_EQ(watched.exit_code, 0) << watched.output;
  EXPECT_THAT(watched.output, HasSubstr("valid quantization of fanpart"));
  EXPECT_TRUE(IsValidResult(LoadProtoOrDie(mesh), ParseResult(ReadFile(result_file))));
  // The bare id works as well, and --json prints the result document.
  const CommandResult by_id =
      RunCommand(Ispq("watch " + job.substr(5) + server_flag_ + " --json --progress=false"));
  ASSERT_EQ(by_id.exit_code, 0) << by_id.output;
  EXPECT_TRUE(ParseResult(by_id.output).valid());

  const CommandResult jobs = RunCommand(Ispq("jobs" + server_flag_));
  ASSERT_EQ(jobs.exit_code, 0) << jobs.output;
  EXPECT_THAT(jobs.output, HasSubstr(job + "  SUCCEEDED  fanpart"));
  const CommandResult jobs_json = RunCommand(Ispq("jobs --json --state SUCCEEDED" + server_flag_));
  ASSERT_EQ(jobs_json.exit_code, 0) << jobs_json.output;
  v1::ListJobsResponse listed;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(jobs_json.output, &listed).ok());
  ASSERT_EQ(listed.jobs_size(), 1);
  EXPECT_EQ(listed.jobs(0).name(), job);

  const CommandResult cancelled = RunCommand(Ispq("cancel " + job + server_flag_));
  ASSERT_EQ(cancelled.exit_code, 0) << cancelled.output;
  EXPECT_THAT(cancelled.output, HasSubstr(job + " SUCCEEDED"));

  const CommandResult health = RunCommand(Ispq("health" + server_flag_));
  EXPECT_EQ(health.exit_code, 0) << health.output;
  EXPECT_THAT(health.output, HasSubstr("SERVING"));
  const CommandResult stats = RunCommand(Ispq("server-stats" + server_flag_));
  ASSERT_EQ(stats.exit_code, 0) << stats.output;
  v1::ServerStats parsed;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(stats.output, &parsed).ok());
  EXPECT_EQ(parsed.accepted_total(), 1);
}

TEST_F(CliTest, ExitCodesScriptsCanRelyOn) {
  ASSERT_NO_FATAL_FAILURE(StartServer({"--workers=1", "--max_queued_jobs=1"}));
  const std::string mesh = RealTMeshPath("hex-me/s07c_notch.tmesh.json");
  // 2: bad command line, checked before anything is sent.
  EXPECT_EQ(RunCommand(Ispq("quantize " + mesh + server_flag_ + " --level 7")).exit_code, 2);
  EXPECT_EQ(RunCommand(Ispq("jobs --state DONE" + server_flag_)).exit_code, 2);
  EXPECT_EQ(RunCommand(Ispq("watch" + server_flag_)).exit_code, 2);
  // 3: unreadable or invalid T-mesh, with the validator's message, as with --local.
  const std::string broken = TempPath("broken.tmesh.json");
  std::string json = ReadFile(mesh);
  json.replace(json.find("\"length\":"), 9, "\"length\":-");
  std::ofstream(broken) << json;
  const CommandResult invalid =
      RunCommand(Ispq("quantize " + broken + server_flag_ + " --level 1"));
  EXPECT_EQ(invalid.exit_code, 3) << invalid.output;
  EXPECT_THAT(invalid.output, HasSubstr("arc 0: length -"));
  // 5: the server does not know the job.
  EXPECT_EQ(RunCommand(Ispq("watch jobs/0000000000000000" + server_flag_)).exit_code, 5);
  // 6: nothing listens there.
  const CommandResult unreachable =
      RunCommand(Ispq("quantize " + mesh + " --server 127.0.0.1:1 --level 1"));
  EXPECT_EQ(unreachable.exit_code, 6) << unreachable.output;
  EXPECT_EQ(RunCommand(Ispq("health --server 127.0.0.1:1")).exit_code, 6);

  // 6: the queue is full (one job runs, one waits).
  const std::string long_mesh = LongRunningMeshFile();
  const CommandResult running =
      RunCommand(Ispq("submit " + long_mesh + server_flag_ + " --level 100 --progress=false"));
  ASSERT_EQ(running.exit_code, 0) << running.output;
  client::QuantizerClient client = ClientOf(*server_);
  const std::string running_job(absl::StripAsciiWhitespace(running.output));
  ASSERT_TRUE(WaitForState(client, running_job, v1::RUNNING).ok());
  const CommandResult waiting = RunCommand(Ispq("submit " + mesh + server_flag_ + " --level 100"));
  ASSERT_EQ(waiting.exit_code, 0) << waiting.output;
  const CommandResult full = RunCommand(Ispq("quantize " + mesh + server_flag_ + " --level 100"));
  EXPECT_EQ(full.exit_code, 6) << full.output;
  EXPECT_THAT(full.output, HasSubstr("queue is full"));

  // 5: the job was cancelled before it ran, so there is no result; 0 for cancel itself.
  const std::string waiting_job(absl::StripAsciiWhitespace(waiting.output));
  const CommandResult cancel = RunCommand(Ispq("cancel " + waiting_job + server_flag_));
  EXPECT_EQ(cancel.exit_code, 0) << cancel.output;
  EXPECT_THAT(cancel.output, HasSubstr("CANCELLED"));
  const CommandResult watch_cancelled = RunCommand(Ispq("watch " + waiting_job + server_flag_));
  EXPECT_EQ(watch_cancelled.exit_code, 5) << watch_cancelled.output;
  EXPECT_THAT(watch_cancelled.output, HasSubstr("cancelled while queued"));

  // 6: the deadline passed.
  const CommandResult late =
      RunCommand(Ispq("watch " + running_job + server_flag_ + " --deadline 0.5"));
  EXPECT_EQ(late.exit_code, 6) << late.output;
  EXPECT_EQ(RunCommand(Ispq("cancel " + running_job + server_flag_)).exit_code, 0);
}

TEST_F(CliTest, BearerTokenFromTheEnvironment) {
  const std::string token_file = TempPath("cli_token");
  std::ofstream(token_file) << "cli-secret\n";
  ASSERT_NO_FATAL_FAILURE(StartServer({"--auth_token_file=" + token_file}));
  const std::string mesh = RealTMeshPath("hex-me/s01c_cube.tmesh.json");
  const CommandResult refused = RunCommand(Ispq("quantize " + mesh + server_flag_ + " --level 1"));
  EXPECT_EQ(refused.exit_code, 5) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("bearer token"));
  const CommandResult accepted = RunCommand("ISPQ_AUTH_TOKEN=cli-secret " +
                                            Ispq("quantize " + mesh + server_flag_ + " --level 1"));
  EXPECT_EQ(accepted.exit_code, 0) << accepted.output;
  const CommandResult flag =
      RunCommand(Ispq("quantize " + mesh + server_flag_ + " --level 1 --auth-token cli-secret"));
  EXPECT_EQ(flag.exit_code, 0) << flag.output;
}

}  // namespace
}  // namespace ispq::testing
