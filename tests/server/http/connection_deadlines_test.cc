// SPDX-License-Identifier: Apache-2.0
#include "server/http/connection_deadlines.h"

#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>

#include "absl/time/clock.h"
#include "absl/time/time.h"
#include "gtest/gtest.h"

namespace ispq::server::http {
namespace {

constexpr absl::Duration kHead = absl::Hours(1);
constexpr absl::Duration kBody = absl::Hours(10);

// A connected pair of sockets: `server` stands for the one libmicrohttpd holds, `client` for
// the client's end, which sees whether the server's end was shut down.
class SocketPair {
 public:
  SocketPair() {
    int fds[2];
    EXPECT_EQ(socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0);
    server_ = fds[0];
    client_ = fds[1];
  }
  ~SocketPair() {
    close(server_);
    close(client_);
  }
  int server() const { return server_; }

  // Whether the client's end reads end-of-stream (the server's end shut down) rather than
  // "nothing yet".
  bool ClientSeesShutdown() const {
    char byte;
    const ssize_t n = recv(client_, &byte, 1, MSG_DONTWAIT);
    const int error = errno;
    if (n == 0) return true;
    EXPECT_EQ(n, -1);
    EXPECT_TRUE(error == EAGAIN || error == EWOULDBLOCK) << error;
    return false;
  }

 private:
  int server_ = -1;
  int client_ = -1;
};

// The connections are libmicrohttpd's opaque handles, only ever used as keys here.
MHD_Connection* Handle(int& slot) { return reinterpret_cast<MHD_Connection*>(&slot); }

// Later than any deadline set so far, but still a time (InfiniteFuture is never "past").
absl::Time Past(absl::Duration deadline) { return absl::Now() + deadline + absl::Minutes(1); }

TEST(ConnectionDeadlinesTest, ShutsDownAConnectionWhoseHeadIsLate) {
  ConnectionDeadlines deadlines(kHead, kBody);
  SocketPair socket;
  int slot = 0;
  deadlines.Opened(Handle(slot), socket.server());
  EXPECT_EQ(deadlines.open(), 1);
  EXPECT_EQ(deadlines.ShutDownLate(absl::Now()), 0);
  EXPECT_FALSE(socket.ClientSeesShutdown());
  EXPECT_EQ(deadlines.ShutDownLate(Past(kHead)), 1);
  EXPECT_TRUE(socket.ClientSeesShutdown());
  EXPECT_EQ(deadlines.shut_down_total(), 1);
  // Still open until libmicrohttpd closes it, which it does on its own thread.
  EXPECT_EQ(deadlines.open(), 1);
}

// A connection shut down once is not counted again while libmicrohttpd gets round to it.
TEST(ConnectionDeadlinesTest, ShutsDownEachLateConnectionOnce) {
  ConnectionDeadlines deadlines(kHead, kBody);
  SocketPair socket;
  int slot = 0;
  deadlines.Opened(Handle(slot), socket.server());
  EXPECT_EQ(deadlines.ShutDownLate(Past(kHead)), 1);
  EXPECT_EQ(deadlines.ShutDownLate(Past(kBody)), 0);
  EXPECT_EQ(deadlines.shut_down_total(), 1);
}

TEST(ConnectionDeadlinesTest, ShutsDownOnlyTheLateOnes) {
  ConnectionDeadlines deadlines(kHead, kBody);
  SocketPair late;
  SocketPair in_body;
  SocketPair answering;
  int slots[3] = {};
  deadlines.Opened(Handle(slots[0]), late.server());
  deadlines.Opened(Handle(slots[1]), in_body.server());
  deadlines.Opened(Handle(slots[2]), answering.server());
  deadlines.HeadReceived(Handle(slots[1]));
  deadlines.HeadReceived(Handle(slots[2]));
  deadlines.RequestReceived(Handle(slots[2]));
  EXPECT_EQ(deadlines.ShutDownLate(Past(kHead)), 1);
  EXPECT_TRUE(late.ClientSeesShutdown());
  EXPECT_FALSE(in_body.ClientSeesShutdown());
  EXPECT_FALSE(answering.ClientSeesShutdown());
  EXPECT_EQ(deadlines.open(), 3);
}

// Once the head is in, the body has body_deadline from then, not what was left of the head's.
TEST(ConnectionDeadlinesTest, TheBodyIsDueBodyDeadlineAfterTheHead) {
  ConnectionDeadlines deadlines(kHead, kBody);
  SocketPair socket;
  int slot = 0;
  deadlines.Opened(Handle(slot), socket.server());
  deadlines.HeadReceived(Handle(slot));
  EXPECT_EQ(deadlines.ShutDownLate(Past(kHead)), 0);
  EXPECT_FALSE(socket.ClientSeesShutdown());
  EXPECT_EQ(deadlines.ShutDownLate(Past(kBody)), 1);
  EXPECT_TRUE(socket.ClientSeesShutdown());
}

// A request waiting for its answer (a long submission, an event stream) is never cut off here.
TEST(ConnectionDeadlinesTest, AReceivedRequestHasNoDeadlineUntilAnswered) {
  ConnectionDeadlines deadlines(kHead, kBody);
  SocketPair socket;
  int slot = 0;
  deadlines.Opened(Handle(slot), socket.server());
  deadlines.HeadReceived(Handle(slot));
  deadlines.RequestReceived(Handle(slot));
  EXPECT_EQ(deadlines.ShutDownLate(absl::Now() + absl::Hours(24 * 365)), 0);
  EXPECT_FALSE(socket.ClientSeesShutdown());
}

// After an answer, a kept-alive connection must send its next head within head_deadline.
TEST(ConnectionDeadlinesTest, TheNextHeadIsDueAfterAnAnswer) {
  ConnectionDeadlines deadlines(kHead, kBody);
  SocketPair socket;
  int slot = 0;
  deadlines.Opened(Handle(slot), socket.server());
  deadlines.HeadReceived(Handle(slot));
  deadlines.RequestReceived(Handle(slot));
  deadlines.RequestDone(Handle(slot));
  EXPECT_EQ(deadlines.ShutDownLate(absl::Now()), 0);
  EXPECT_EQ(deadlines.ShutDownLate(Past(kHead)), 1);
  EXPECT_TRUE(socket.ClientSeesShutdown());
}

// A closed connection's socket (whose number the kernel may give to another) is never touched,
// and late callbacks for it do not bring it back.
TEST(ConnectionDeadlinesTest, ForgetsAClosedConnection) {
  ConnectionDeadlines deadlines(kHead, kBody);
  SocketPair socket;
  int slot = 0;
  deadlines.Opened(Handle(slot), socket.server());
  deadlines.Closed(Handle(slot));
  EXPECT_EQ(deadlines.open(), 0);
  deadlines.HeadReceived(Handle(slot));
  deadlines.RequestDone(Handle(slot));
  EXPECT_EQ(deadlines.open(), 0);
  EXPECT_EQ(deadlines.ShutDownLate(Past(kBody)), 0);
  EXPECT_FALSE(socket.ClientSeesShutdown());
  EXPECT_EQ(deadlines.shut_down_total(), 0);
}

}  // namespace
}  // namespace ispq::server::http
