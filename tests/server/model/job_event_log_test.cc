// SPDX-License-Identifier: Apache-2.0
#include "server/model/job_event_log.h"

#include <vector>

#include "gtest/gtest.h"

namespace ispq::server {
namespace {

v1::QuantizeEvent Progress(double objective) {
  v1::QuantizeEvent event;
  event.mutable_progress()->set_objective(objective);
  return event;
}

TEST(JobEventLogTest, NumbersEventsInOrder) {
  JobEventLog log;
  v1::QuantizeEvent accepted;
  accepted.mutable_accepted();
  EXPECT_EQ(log.Append(accepted), 0);
  EXPECT_EQ(log.Append(Progress(3)), 1);
  EXPECT_EQ(log.emitted(), 2);
  ASSERT_NE(log.FirstAtOrAfter(0), nullptr);
  EXPECT_TRUE(log.FirstAtOrAfter(0)->has_accepted());
  EXPECT_EQ(log.FirstAtOrAfter(1)->progress().objective(), 3);
  EXPECT_EQ(log.FirstAtOrAfter(2), nullptr);
  EXPECT_FALSE(log.ended());
}

TEST(JobEventLogTest, KeepsOnlyTheLatestSnapshotOfEachKind) {
  JobEventLog log;
  log.Append(v1::QuantizeEvent());  // 0, accepted-like
  for (int i = 1; i <= 1000; ++i) log.Append(Progress(i));
  v1::QuantizeEvent intermediate;
  intermediate.mutable_intermediate()->add_q(1);
  log.Append(intermediate);  // 1001
  log.Append(intermediate);  // 1002 replaces 1001
  log.Append(Progress(-1));  // 1003 replaces 1000
  // A reader at any old number skips to the next kept event.
  EXPECT_EQ(log.FirstAtOrAfter(1)->sequence(), 1002);
  EXPECT_EQ(log.FirstAtOrAfter(1003)->progress().objective(), -1);
  v1::QuantizeEvent result;
  result.mutable_result();
  EXPECT_EQ(log.Append(result), 1004);
  EXPECT_TRUE(log.ended());
  // The first event, the latest progress and the result, which supersedes the intermediate q.
  std::vector<int64_t> kept;
  for (const v1::QuantizeEvent* e = log.FirstAtOrAfter(0); e != nullptr;
       e = log.FirstAtOrAfter(e->sequence() + 1)) {
    kept.push_back(e->sequence());
  }
  EXPECT_EQ(kept, (std::vector<int64_t>{0, 1003, 1004}));
}

}  // namespace
}  // namespace ispq::server
