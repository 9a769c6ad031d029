// SPDX-License-Identifier: Apache-2.0
// Every suspend and resume of a libmicrohttpd connection by the HTTP side goes through here, so
// that the server knows how many are suspended: libmicrohttpd aborts the process when it is
// stopped with a connection still suspended, so the server stops it only once none is
// (server/http/http_server.h). Thread-safe.
#ifndef ISPQ_SERVER_HTTP_SUSPENSIONS_H_
#define ISPQ_SERVER_HTTP_SUSPENSIONS_H_

#include <atomic>

struct MHD_Connection;

namespace ispq::server::http {

class Suspensions {
 public:
  // Only on the connection's event thread, from its request or content callback.
  void Suspend(MHD_Connection* connection);
  // From any thread, once per Suspend.
  void Resume(MHD_Connection* connection);
  int suspended() const { return suspended_.load(); }

 private:
  std::atomic<int> suspended_{0};
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_SUSPENSIONS_H_
