// SPDX-License-Identifier: Apache-2.0
// PostgresListener (server/store/postgres/postgres_listener.h) on a real PostgreSQL:
// notifications of its channels reach the handler with their payloads from the moment the
// constructor returns, others do not, and after the database restarts it listens again and says
// that notifications may have been missed.
#include "server/store/postgres/postgres_listener.h"

#include <memory>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/synchronization/mutex.h"
#include "gtest/gtest.h"
#include "server/store/postgres/postgres_connections.h"
#include "tests/support/bounded_wait.h"
#include "tests/support/postgres_suite.h"

namespace ispq::server {
namespace {

using ::ispq::testing::kSafetyNet;

// What the handler was called with, as `channel:payload`, in order.
class Heard {
 public:
  PostgresListener::Handler Handler() {
    return [this](const std::string& channel, const std::string& payload) {
      absl::MutexLock lock(&mutex_);
      heard_.push_back(absl::StrCat(channel, ":", payload));
    };
  }
  // Waits until `count` calls were heard; all of them so far, joined by spaces.
  std::string AwaitCount(size_t count) {
    absl::MutexLock lock(&mutex_);
    auto enough = [&]() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_) { return heard_.size() >= count; };
    mutex_.AwaitWithTimeout(absl::Condition(&enough), kSafetyNet);
    return absl::StrJoin(heard_, " ");
  }

 private:
  absl::Mutex mutex_;
  std::vector<std::string> heard_ ABSL_GUARDED_BY(mutex_);
};

class PostgresListenerTest : public ispq::testing::PostgresSuite {
 protected:
  static std::string Uri() { return WithConnectionDefaults(postgres_->uri(), absl::Seconds(5)); }
  static void Notify(const std::string& channel, const std::string& payload) {
    ASSERT_TRUE(
        postgres_->Sql(absl::StrCat("SELECT pg_notify('", channel, "', '", payload, "')")).ok());
  }
};

// Sent right after the constructor returns: a listener that were not subscribed by then would
// miss them. Notifications of one session arrive in order, so once `b` is heard, `other` would
// have been heard before it.
TEST_F(PostgresListenerTest, HandsEachNotificationOfItsChannelsToTheHandler) {
  Heard heard;
  PostgresListener listener(Uri(), {"a", "b"}, heard.Handler());
  Notify("a", "first");
  Notify("other", "ignored");
  Notify("b", "second");
  Notify("a", "");
  EXPECT_EQ(heard.AwaitCount(3), "a:first b:second a:");
}

TEST_F(PostgresListenerTest, AfterTheDatabaseRestartsItListensAgainAndSaysSo) {
  Heard heard;
  PostgresListener listener(Uri(), {"a"}, heard.Handler());
  Notify("a", "before");
  ASSERT_EQ(heard.AwaitCount(1), "a:before");
  ASSERT_TRUE(postgres_->Restart().ok());
  // The empty channel: whatever was sent while it was not listening must be looked at again.
  ASSERT_EQ(heard.AwaitCount(2), "a:before :");
  Notify("a", "after");
  EXPECT_EQ(heard.AwaitCount(3), "a:before : a:after");
}

}  // namespace
}  // namespace ispq::server
