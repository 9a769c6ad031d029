// SPDX-License-Identifier: Apache-2.0
// SocketDeadlines (server/store/postgres/socket_deadlines.h): a blocking read on a socket whose
// peer never answers returns once its deadline passes, and a guard gone before its deadline leaves
// the socket alone.
#include "server/store/postgres/socket_deadlines.h"

#include <sys/socket.h>
#include <unistd.h>

#include "absl/time/clock.h"
#include "gtest/gtest.h"

namespace ispq::server {
namespace {

class SocketPair {
 public:
  SocketPair() { EXPECT_EQ(socketpair(AF_UNIX, SOCK_STREAM, 0, fds_), 0); }
  ~SocketPair() {
    close(fds_[0]);
    close(fds_[1]);
  }
  int ours() const { return fds_[0]; }
  int peer() const { return fds_[1]; }

 private:
  int fds_[2] = {-1, -1};
};

TEST(SocketDeadlinesTest, ABlockedReadReturnsWhenItsDeadlinePasses) {
  SocketDeadlines deadlines(absl::Milliseconds(10));
  SocketPair sockets;
  char byte = 0;
  ssize_t read_bytes = 1;
  bool expired = false;
  {
    SocketDeadlines::Guard guard(deadlines, sockets.ours(), absl::Now() + absl::Milliseconds(50));
    read_bytes = read(sockets.ours(), &byte, 1);  // the peer never writes
    expired = guard.expired();
  }
  EXPECT_EQ(read_bytes, 0) << "shut down: end of stream instead of waiting forever";
  EXPECT_TRUE(expired);
}

TEST(SocketDeadlinesTest, AGuardGoneBeforeItsDeadlineLeavesTheSocketAlone) {
  SocketDeadlines deadlines(absl::Milliseconds(10));
  SocketPair sockets;
  {
    SocketDeadlines::Guard guard(deadlines, sockets.ours(), absl::Now() + absl::Milliseconds(30));
    EXPECT_FALSE(guard.expired());
  }
  absl::SleepFor(absl::Milliseconds(100));  // well past the deadline of the gone guard
  ASSERT_EQ(write(sockets.peer(), "x", 1), 1);
  char byte = 0;
  EXPECT_EQ(read(sockets.ours(), &byte, 1), 1);
  EXPECT_EQ(byte, 'x');
}

}  // namespace
}  // namespace ispq::server
