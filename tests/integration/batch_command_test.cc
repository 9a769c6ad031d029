// SPDX-License-Identifier: Apache-2.0
// `ispq batch` (client/batch_command.h) against real servers: the 62 real T-meshes at 8 levels
// (496 jobs) while the server is killed and restarted in the middle, with an in-memory store
// (the jobs it had are lost: the batch submits them again) and with a PostgreSQL store (they
// survive: the batch gets them back by request id, and the database holds exactly one job per
// request). Every result file is checked by the validator and equals the in-process answer. A
// second run keeps every result and submits nothing; a broken mesh fails its own jobs only, and
// is named.
#include <signal.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/proto/quantization_proto.h"
#include "core/quantizer.h"
#include "gmock/gmock.h"
#include "google/protobuf/util/json_util.h"
#include "gtest/gtest.h"
#include "tests/integration/service_test_support.h"
#include "tests/support/child_process.h"
#include "tests/support/postgres_instance.h"
#include "tests/support/test_data.h"

namespace ispq::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr int kLevels[] = {0, 1, 5, 10, 17, 25, 50, 100};
constexpr absl::Duration kSafetyNet = absl::Seconds(600);  // only a hang reaches it

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream contents;
  contents << in.rdbuf();
  return contents.str();
}

int CountLines(const std::string& text, const std::string& part) {
  int count = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) count += line.find(part) != std::string::npos;
  return count;
}

int CountResultFiles(const std::string& out_dir) {
  int count = 0;
  std::error_code error;
  for (fs::recursive_directory_iterator it(out_dir, error), end; !error && it != end;
       it.increment(error)) {
    if (it->path().string().ends_with(".result.json")) ++count;
  }
  return count;
}

// `ispq batch` running as a child process; its output goes to a file.
class BatchRun {
 public:
  BatchRun(const std::vector<std::string>& args, const std::string& log) : log_(log) {
    fs::remove(log_);
    ChildProcessOptions options;
    options.argv = {ISPQ_CLI_PATH, "batch", "--progress=true"};
    options.argv.insert(options.argv.end(), args.begin(), args.end());
    options.output_path = log_;
    absl::StatusOr<pid_t> pid = StartChildProcess(options);
    EXPECT_TRUE(pid.ok()) << pid.status();
    pid_ = pid.value_or(-1);
  }
  // The exit code (-1 if it was killed or did not end within the safety net).
  int Wait() {
    const std::optional<int> status = WaitForChild(pid_, kSafetyNet);
    return status.has_value() && WIFEXITED(*status) ? WEXITSTATUS(*status) : -1;
  }
  bool running() { return !PollChild(pid_).has_value(); }
  std::string output() const { return ReadFile(log_); }

 private:
  std::string log_;
  pid_t pid_ = -1;
};

class BatchCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    out_dir_ = ::testing::TempDir() + "batch-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(out_dir_);
  }

  std::vector<std::string> BatchArgs(const std::string& address, int concurrency = 4) const {
    return {RealTMeshDir(), "--levels=0,1,5,10,17,25,50,100", "--out-dir=" + out_dir_,
            "--server=" + address, absl::StrCat("--concurrency=", concurrency)};
  }

  // Runs the whole batch; once `restart_after` result files exist, kills the server with SIGKILL
  // and starts it again, on the same port, with `flags`.
  void RunWithRestart(std::unique_ptr<ServerProcess>& server, const std::vector<std::string>& flags,
                      int restart_after) {
    const std::string port = absl::StrCat(server->port());
    BatchRun batch(BatchArgs(server->address()), out_dir_ + ".log");
    const absl::Time deadline = absl::Now() + kSafetyNet;
    while (CountResultFiles(out_dir_) < restart_after && batch.running() &&
           absl::Now() < deadline) {
      absl::SleepFor(absl::Milliseconds(5));
    }
    ASSERT_TRUE(batch.running()) << "the batch ended before the restart:\n" << batch.output();
    const int before_kill = CountResultFiles(out_dir_);
    server->Signal(SIGKILL);
    ASSERT_TRUE(server->WaitForExit(kSafetyNet).has_value());
    std::vector<std::string> restarted_flags = flags;
    restarted_flags.push_back("--listen=127.0.0.1:" + port);  // the batch's address
    server = StartServerOrFail(restarted_flags);
    ASSERT_NE(server, nullptr);
    const int exit_code = batch.Wait();
    const std::string output = batch.output();
    ASSERT_EQ(exit_code, 0) << output;
    EXPECT_LT(before_kill, 496) << "the kill came after the last result";
    std::cout << "killed the server after " << before_kill << " of 496 results; the batch said "
              << CountLines(output, "submitting it again") << " times that a job was gone and "
              << CountLines(output, "retrying in") << " times that it would retry a call\n";
  }

  // Every one of the 496 result files is valid and equal to the in-process answer.
  void ExpectEveryResultValidAndLocal() {
    int checked = 0;
    for (const std::string& path : RealTMeshFiles()) {
      const v1::TMesh proto = LoadProtoOrDie(path);
      const TMesh mesh = TMeshOrDie(proto);
      const std::string relative = fs::relative(path, RealTMeshDir()).generic_string();
      const std::string stem = relative.substr(0, relative.find(".tmesh."));
      for (const int level : kLevels) {
        const std::string result_path =
            absl::StrCat(out_dir_, "/", stem, ".L", level, ".result.json");
        v1::QuantizationResult result;
        ASSERT_TRUE(
            google::protobuf::util::JsonStringToMessage(ReadFile(result_path), &result).ok())
            << result_path;
        ASSERT_TRUE(IsValidResult(proto, result)) << result_path;
        v1::QuantizationOptions options;
        options.mutable_scaling()->set_level_percent(level);
        absl::StatusOr<QuantizeOptions> local_options = QuantizeOptionsFromProto(options, mesh);
        ASSERT_TRUE(local_options.ok()) << local_options.status();
        absl::StatusOr<QuantizeResult> local = Quantize(mesh, *local_options);
        ASSERT_TRUE(local.ok()) << local.status();
        EXPECT_EQ(absl::StrJoin(result.q(), ","), absl::StrJoin(local->q, ",")) << result_path;
        ++checked;
      }
    }
    EXPECT_EQ(checked, 496);
    EXPECT_EQ(CountResultFiles(out_dir_), 496);
  }

  // The jobs a server holds now, by request id: none may appear twice.
  static std::map<std::string, int> JobsByRequestId(client::QuantizerClient& client) {
    std::map<std::string, int> counts;
    v1::ListJobsRequest request;
    request.set_page_size(1000);
    do {
      absl::StatusOr<v1::ListJobsResponse> page = client.ListJobs(request);
      EXPECT_TRUE(page.ok()) << page.status();
      if (!page.ok()) break;
      for (const v1::Job& job : page->jobs()) ++counts[job.request_id()];
      request.set_page_token(page->next_page_token());
    } while (!request.page_token().empty());
    return counts;
  }

  std::string out_dir_;
};

TEST_F(BatchCommandTest, RidesOutARestartOfAnInMemoryServerAndKeepsItsResultsOnARerun) {
  const std::vector<std::string> flags = {"--workers=2", "--max_queued_jobs=1000"};
  std::unique_ptr<ServerProcess> server = StartServerOrFail(flags);
  ASSERT_NE(server, nullptr);
  ASSERT_NO_FATAL_FAILURE(RunWithRestart(server, flags, 150));
  ASSERT_NO_FATAL_FAILURE(ExpectEveryResultValidAndLocal());
  client::QuantizerClient client = ClientOf(*server);
  for (const auto& [request_id, count] : JobsByRequestId(client)) {
    EXPECT_TRUE(request_id.starts_with("batch-")) << request_id;
    EXPECT_EQ(count, 1) << request_id << " was run twice by the restarted server";
  }

  // A rerun finds every result and submits nothing.
  const absl::StatusOr<v1::ServerStats> before = client.GetServerStats();
  ASSERT_TRUE(before.ok());
  BatchRun rerun(BatchArgs(server->address()), out_dir_ + ".rerun.log");
  ASSERT_EQ(rerun.Wait(), 0) << rerun.output();
  const absl::StatusOr<v1::ServerStats> after = client.GetServerStats();
  ASSERT_TRUE(after.ok());
  EXPECT_EQ(after->accepted_total(), before->accepted_total());
  EXPECT_THAT(rerun.output(), HasSubstr("[496/496 done, 0 failed, 0 running]"));
  EXPECT_THAT(ReadFile(out_dir_ + "/summary.tsv"), HasSubstr("\tKEPT\t"));
}

TEST_F(BatchCommandTest, GetsItsJobsBackFromAStoreThatSurvivesTheRestart) {
  absl::StatusOr<std::unique_ptr<PostgresInstance>> postgres = PostgresInstance::Start();
  ASSERT_TRUE(postgres.ok()) << postgres.status();
  absl::StatusOr<std::string> uri = (*postgres)->CreateDatabase("batch");
  ASSERT_TRUE(uri.ok()) << uri.status();
  const std::vector<std::string> flags = {"--workers=2", "--max_queued_jobs=1000",
                                          "--job_store=" + *uri, "--job_lease_seconds=1.5"};
  std::unique_ptr<ServerProcess> server = StartServerOrFail(flags);
  ASSERT_NE(server, nullptr);
  ASSERT_NO_FATAL_FAILURE(RunWithRestart(server, flags, 150));
  ASSERT_NO_FATAL_FAILURE(ExpectEveryResultValidAndLocal());
  client::QuantizerClient client = ClientOf(*server);
  const std::map<std::string, int> jobs = JobsByRequestId(client);
  EXPECT_EQ(jobs.size(), 496u) << "one job per request, across the restart";
  for (const auto& [request_id, count] : jobs) {
    EXPECT_EQ(count, 1) << request_id << " has " << count << " jobs";
  }
}

TEST_F(BatchCommandTest, ABrokenMeshFailsItsOwnJobsOnlyAndIsNamed) {
  std::unique_ptr<ServerProcess> server = StartServerOrFail({"--workers=2"});
  ASSERT_NE(server, nullptr);
  const std::string inputs = ::testing::TempDir() + "batch-inputs";
  fs::remove_all(inputs);
  fs::create_directories(inputs);
  fs::copy_file(RealTMeshPath("hex-me/s07c_notch.tmesh.json"), inputs + "/notch.tmesh.json");
  std::ofstream(inputs + "/broken.tmesh.json")
      << R"({"formatVersion": 1, "arcs": [{"lenght": 1}]})";
  BatchRun batch(
      {inputs, "--levels=10,50", "--out-dir=" + out_dir_, "--server=" + server->address()},
      out_dir_ + ".log");
  EXPECT_EQ(batch.Wait(), 3);  // invalid input
  const std::string output = batch.output();
  EXPECT_THAT(output, HasSubstr("2 of 4 jobs have no valid result: broken L10, broken L50"));
  // The parser's message names the bad field, in the summary too.
  EXPECT_THAT(output,
              HasSubstr("FAILED broken L10: " + inputs +
                        "/broken.tmesh.json: not a T-mesh JSON document: (arcs[0]) lenght"));
  EXPECT_EQ(CountResultFiles(out_dir_), 2);
  const std::string summary = ReadFile(out_dir_ + "/summary.tsv");
  EXPECT_THAT(summary, HasSubstr("notch.tmesh.json\tL10\tSUCCEEDED"));
  EXPECT_THAT(summary, HasSubstr("broken.tmesh.json\tL50\tFAILED"));
}

}  // namespace
}  // namespace ispq::testing
