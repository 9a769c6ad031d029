// SPDX-License-Identifier: Apache-2.0
// ServerMetrics (server/metrics/server_metrics.h): each event counts in its own field of
// GetServerStats, jobs by their final state, solve and queue-wait times in their histograms
// (runs that never solved leave the solve histogram alone), and the mean solve time that retry
// hints are made from.
#include "server/metrics/server_metrics.h"

#include <thread>
#include <vector>

#include "gtest/gtest.h"

namespace ispq::server {
namespace {

v1::ServerStats StatsOf(const ServerMetrics& metrics) {
  v1::ServerStats stats;
  metrics.FillProto(stats);
  return stats;
}

TEST(ServerMetricsTest, EachCounterFillsItsOwnField) {
  ServerMetrics metrics;
  metrics.RecordAccepted();
  for (int i = 0; i < 2; ++i) metrics.RecordRejectedQueueFull();
  for (int i = 0; i < 3; ++i) metrics.RecordRejectedInvalid();
  for (int i = 0; i < 4; ++i) metrics.RecordRejectedMemory();
  for (int i = 0; i < 5; ++i) metrics.RecordEvictedResult();
  for (int i = 0; i < 6; ++i) metrics.RecordEvictedMesh();
  const v1::ServerStats stats = StatsOf(metrics);
  EXPECT_EQ(stats.accepted_total(), 1);
  EXPECT_EQ(stats.rejected_queue_full_total(), 2);
  EXPECT_EQ(stats.rejected_invalid_total(), 3);
  EXPECT_EQ(stats.rejected_memory_total(), 4);
  EXPECT_EQ(stats.evicted_results_total(), 5);
  EXPECT_EQ(stats.evicted_meshes_total(), 6);
  EXPECT_EQ(stats.finished_total().succeeded() + stats.finished_total().failed() +
                stats.finished_total().cancelled(),
            0);
}

TEST(ServerMetricsTest, FinishedJobsCountByFinalStateAndOnlySolvesAreTimed) {
  ServerMetrics metrics;
  metrics.RecordFinished(v1::SUCCEEDED, 0.5);
  metrics.RecordFinished(v1::SUCCEEDED, 1.5);
  metrics.RecordFinished(v1::CANCELLED, 2.0);  // interrupted, with its best result
  metrics.RecordFinished(v1::CANCELLED, -1);   // cancelled before it started
  metrics.RecordFinished(v1::FAILED, -1);
  // Not final: counted nowhere.
  metrics.RecordFinished(v1::RUNNING, -1);
  metrics.RecordFinished(v1::QUEUED, -1);
  const v1::ServerStats stats = StatsOf(metrics);
  EXPECT_EQ(stats.finished_total().succeeded(), 2);
  EXPECT_EQ(stats.finished_total().cancelled(), 2);
  EXPECT_EQ(stats.finished_total().failed(), 1);
  EXPECT_EQ(stats.solve_seconds().count(), 3);
  EXPECT_DOUBLE_EQ(stats.solve_seconds().sum(), 4.0);
  EXPECT_EQ(stats.queue_wait_seconds().count(), 0);
}

TEST(ServerMetricsTest, QueueWaitsGoToTheirOwnHistogramInSeconds) {
  ServerMetrics metrics;
  metrics.RecordStarted(absl::Milliseconds(250));
  metrics.RecordStarted(absl::Seconds(2));
  const v1::ServerStats stats = StatsOf(metrics);
  EXPECT_EQ(stats.queue_wait_seconds().count(), 2);
  EXPECT_DOUBLE_EQ(stats.queue_wait_seconds().sum(), 2.25);
  EXPECT_EQ(stats.solve_seconds().count(), 0);
  EXPECT_DOUBLE_EQ(metrics.MeanSolveSeconds(), 0.0) << "queue waits are no solves";
}

TEST(ServerMetricsTest, MeanSolveSecondsIsZeroBeforeTheFirstSolve) {
  ServerMetrics metrics;
  EXPECT_DOUBLE_EQ(metrics.MeanSolveSeconds(), 0.0);
  metrics.RecordFinished(v1::FAILED, -1);
  EXPECT_DOUBLE_EQ(metrics.MeanSolveSeconds(), 0.0);
  metrics.RecordFinished(v1::SUCCEEDED, 1.0);
  metrics.RecordFinished(v1::SUCCEEDED, 3.0);
  EXPECT_DOUBLE_EQ(metrics.MeanSolveSeconds(), 2.0);
}

// The service, the admission threads and the workers record at once.
TEST(ServerMetricsTest, ConcurrentRecordsAreAllCounted) {
  ServerMetrics metrics;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&metrics] {
      for (int i = 0; i < 1000; ++i) {
        metrics.RecordAccepted();
        metrics.RecordStarted(absl::Milliseconds(1));
        metrics.RecordFinished(v1::SUCCEEDED, 0.001);
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  const v1::ServerStats stats = StatsOf(metrics);
  EXPECT_EQ(stats.accepted_total(), 4000);
  EXPECT_EQ(stats.finished_total().succeeded(), 4000);
  EXPECT_EQ(stats.solve_seconds().count(), 4000);
  EXPECT_EQ(stats.queue_wait_seconds().count(), 4000);
}

}  // namespace
}  // namespace ispq::server
