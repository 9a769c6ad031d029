// SPDX-License-Identifier: Apache-2.0
#include "server/jobs/progress_publisher.h"

#include <thread>
#include <vector>

#include "gtest/gtest.h"
#include "tests/server/server_test_jobs.h"

namespace ispq::server {
namespace {

// Every kept event of a job, in order.
std::vector<v1::QuantizeEvent> KeptEvents(const Job& job) {
  std::vector<v1::QuantizeEvent> events;
  for (int64_t next = 0;;) {
    Job::StreamStep step = job.NextForStream(next);
    if (!step.event.has_value()) return events;
    next = step.event->sequence() + 1;
    events.push_back(*step.event);
  }
}

ProgressEvent Report(QuantizationPhase phase, double objective, bool separating,
                     std::span<const int64_t> q = {}) {
  return ProgressEvent{.phase = phase,
                       .iteration = 1,
                       .separation_round = 0,
                       .objective = objective,
                       .violated_constraints = 0,
                       .separating = separating,
                       .elapsed_seconds = 0,
                       .lp_solves = 0,
                       .q = q};
}

TEST(ProgressPublisherTest, ReportsTheFirstEventPhaseChangesAndThenAtMostOnePerInterval) {
  std::shared_ptr<Job> job = NewNotchJob("p");
  ProgressPublisher publisher(*job, absl::Hours(1), absl::ZeroDuration());
  EXPECT_FALSE(publisher.WantsQuantization());
  publisher.OnProgress(Report(QuantizationPhase::kGreedy, 10, false));     // first: sent
  publisher.OnProgress(Report(QuantizationPhase::kGreedy, 9, false));      // within the interval
  publisher.OnProgress(Report(QuantizationPhase::kSeparation, 8, false));  // new phase: sent
  const std::vector<v1::QuantizeEvent> events = KeptEvents(*job);
  // accepted + the latest progress (snapshots replace each other), numbered 0 and 2.
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].sequence(), 2);
  EXPECT_EQ(events[1].progress().phase(), v1::SEPARATION);
  EXPECT_EQ(events[1].progress().objective(), 8);
}

TEST(ProgressPublisherTest, SendsIntermediateQuantizationsOnlyWhenTheyImprove) {
  std::shared_ptr<Job> job = NewNotchJob("i");
  ProgressPublisher publisher(*job, absl::Milliseconds(10), absl::Milliseconds(10));
  const std::vector<int64_t> q(75, 1);
  const auto publish = [&](double objective, bool separating) {
    while (!publisher.WantsQuantization())
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    publisher.OnProgress(Report(QuantizationPhase::kGreedy, objective, separating, q));
    const std::vector<v1::QuantizeEvent> events = KeptEvents(*job);
    for (const v1::QuantizeEvent& event : events) {
      if (event.has_intermediate()) return event.intermediate().progress().objective();
    }
    return -1.0;
  };
  EXPECT_EQ(publish(50, false), 50);
  EXPECT_EQ(publish(40, false), 40);  // lower objective
  EXPECT_EQ(publish(45, false), 40);  // worse: not sent
  EXPECT_EQ(publish(60, true), 60);   // separating beats any non-separating q
  EXPECT_EQ(publish(30, false), 60);  // not separating any more: not sent
  EXPECT_EQ(publish(55, true), 55);
}

}  // namespace
}  // namespace ispq::server
