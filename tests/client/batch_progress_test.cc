// SPDX-License-Identifier: Apache-2.0
#include "client/batch_progress.h"

#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace ispq::cli {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

// What a BatchProgress wrote to a file (not a terminal: the plain form a log gets).
class BatchProgressTest : public ::testing::Test {
 protected:
  void SetUp() override { out_ = std::tmpfile(); }
  void TearDown() override { std::fclose(out_); }
  std::string Written() {
    std::fflush(out_);
    std::rewind(out_);
    std::string text;
    char buffer[4096];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, out_)) > 0;) text.append(buffer, n);
    return text;
  }
  FILE* out_ = nullptr;
};

TEST_F(BatchProgressTest, ALogGetsFinishedJobsNoticesAndTotalsButNoLiveLines) {
  BatchProgress progress(out_, 3, /*enabled=*/true);
  progress.Update(0, "a L5", "jobs/1 GREEDY objective 12 after 0.1s");
  progress.Notice(1, "b L5", "server unavailable; retrying in 100ms");
  progress.Finished(0, "a L5", true, "objective 10");
  progress.Finished(1, "b L5", false, "b.tmesh.json: arc 3: length -1");
  progress.Close();
  const std::string text = Written();
  EXPECT_THAT(text, Not(HasSubstr("GREEDY")));  // live lines are for terminals
  EXPECT_THAT(text, HasSubstr("b L5: server unavailable; retrying in 100ms\n"));
  EXPECT_THAT(text, HasSubstr("done   a L5: objective 10\n"));
  EXPECT_THAT(text, HasSubstr("FAILED b L5: b.tmesh.json: arc 3: length -1\n"));
  EXPECT_THAT(text, HasSubstr("[1/3 done, 0 failed, 1 running]\n"));  // b still running
  EXPECT_THAT(text, HasSubstr("[2/3 done, 1 failed, 0 running]\n"));
  EXPECT_THAT(text, Not(HasSubstr("\033[")));  // no cursor movement outside a terminal
}

TEST_F(BatchProgressTest, DisabledWritesNothing) {
  BatchProgress progress(out_, 1, /*enabled=*/false);
  progress.Update(0, "a", "running");
  progress.Notice(0, "a", "retrying");
  progress.Finished(0, "a", true, "objective 1");
  progress.Close();
  EXPECT_EQ(Written(), "");
}

TEST_F(BatchProgressTest, WorkersReportingAtOnceAreCountedOnce) {
  constexpr int kJobs = 400;
  BatchProgress progress(out_, kJobs, /*enabled=*/true);
  std::vector<std::thread> workers;
  for (int w = 0; w < 4; ++w) {
    workers.emplace_back([&progress, w] {
      for (int i = w; i < kJobs; i += 4) {
        progress.Update(i, "job", "running");
        progress.Finished(i, "job", i % 10 != 0, "ended");
      }
    });
  }
  for (std::thread& worker : workers) worker.join();
  EXPECT_THAT(Written(), HasSubstr("[400/400 done, 40 failed, 0 running]\n"));
}

}  // namespace
}  // namespace ispq::cli
