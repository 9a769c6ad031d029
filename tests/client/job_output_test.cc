// SPDX-License-Identifier: Apache-2.0
// How the CLI shows a remote job: the event printer's accepted line and progress (nothing when
// disabled), errors as "ispq: <context>: <message>" with the exit code of their status, and an
// outcome shown like a local result or, without a result, as an error named after the job (or
// the server when the job never got a name).
#include "client/job_output.h"

#include <filesystem>
#include <string>

#include "client/exit_codes.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/client/client_test_files.h"

namespace ispq::cli {
namespace {

using ::testing::HasSubstr;

v1::QuantizeEvent Accepted() {
  v1::QuantizeEvent event;
  event.set_job("jobs/abc");
  v1::JobAccepted* accepted = event.mutable_accepted();
  accepted->set_mesh_display_name("cube");
  accepted->mutable_mesh_stats()->set_arcs(12);
  accepted->set_scaling(2.5);
  accepted->set_queue_position(3);
  return event;
}

v1::QuantizeEvent Progress(double seconds) {
  v1::QuantizeEvent event;
  event.set_job("jobs/abc");
  event.mutable_progress()->set_phase(v1::GREEDY);
  event.mutable_progress()->set_elapsed_seconds(seconds);
  return event;
}

TEST(JobOutputTest, TheEventPrinterShowsAcceptanceAndProgressOnStderr) {
  ::testing::internal::CaptureStderr();
  {
    JobEventPrinter printer(/*enabled=*/true);
    EXPECT_TRUE(printer.OnEvent(Accepted()));
    EXPECT_TRUE(printer.OnEvent(Progress(0.0)));
    v1::QuantizeEvent intermediate;
    intermediate.mutable_intermediate()->mutable_progress()->set_phase(v1::FINAL);
    intermediate.mutable_intermediate()->mutable_progress()->set_elapsed_seconds(1.0);
    EXPECT_TRUE(printer.OnEvent(intermediate));
    printer.Finish();
  }
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_THAT(err, HasSubstr("jobs/abc accepted: cube, 12 arcs, scaling 2.5, 3 jobs ahead\n"));
  EXPECT_THAT(err, HasSubstr("phase=greedy"));
  EXPECT_THAT(err, HasSubstr("phase=final"));  // an intermediate result's progress
}

TEST(JobOutputTest, ADisabledPrinterPrintsNothingAndNeverStopsTheStream) {
  ::testing::internal::CaptureStderr();
  {
    JobEventPrinter printer(/*enabled=*/false);
    EXPECT_TRUE(printer.OnEvent(Accepted()));
    EXPECT_TRUE(printer.OnEvent(Progress(1.0)));
    printer.Finish();
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(JobOutputTest, ErrorsArePrintedWithTheirContextAndMappedToExitCodes) {
  const struct {
    absl::Status status;
    int exit_code;
  } cases[] = {
      {absl::InvalidArgumentError("bad mesh"), kExitInvalidInput},
      {absl::UnavailableError("down"), kExitUnavailable},
      {absl::ResourceExhaustedError("queue full"), kExitUnavailable},
      {absl::DeadlineExceededError("late"), kExitUnavailable},
      {absl::NotFoundError("no such job"), kExitFailed},
      {absl::InternalError("boom"), kExitFailed},
  };
  for (const auto& c : cases) {
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(ReportError("jobs/x", c.status), c.exit_code) << c.status;
    EXPECT_EQ(::testing::internal::GetCapturedStderr(),
              "ispq: jobs/x: " + std::string(c.status.message()) + "\n");
  }
}

TEST(JobOutputTest, AnOutcomeWithoutResultIsAnErrorNamedAfterTheJobOrServer) {
  RemoteCommandOptions options;
  options.connection.address = "server.example:50051";
  client::JobOutcome outcome;
  outcome.status = absl::UnavailableError("connection refused");
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(ReportJobOutcome(outcome, options), kExitUnavailable);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(),
            "ispq: server.example:50051: connection refused\n");

  outcome.job = "jobs/abc";
  outcome.status = absl::InvalidArgumentError("arc 3: length 0");
  outcome.job_ended = true;
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(ReportJobOutcome(outcome, options), kExitInvalidInput);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "ispq: jobs/abc: arc 3: length 0\n");
}

TEST(JobOutputTest, AnOutcomeWithResultIsShownLikeALocalResult) {
  const testing::TestFolder folder;
  RemoteCommandOptions options;
  options.json = true;
  options.out_path = folder.Path("result.json");
  client::JobOutcome outcome;
  outcome.job = "jobs/abc";
  outcome.result = testing::GridResult();
  outcome.result->set_valid(false);
  ::testing::internal::CaptureStdout();
  EXPECT_EQ(ReportJobOutcome(outcome, options), kExitInvalidResult);
  EXPECT_THAT(::testing::internal::GetCapturedStdout(), HasSubstr("\"valid\":false"));
  EXPECT_TRUE(std::filesystem::exists(options.out_path));
}

}  // namespace
}  // namespace ispq::cli
