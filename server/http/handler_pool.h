// SPDX-License-Identifier: Apache-2.0
// A few threads of the HTTP side's own that run the routes which may wait (on the job store) or
// work for long (converting a large body), so that the event thread that reads and writes every
// connection never does (server/http/http_router.h). Tasks run in the order posted; tasks still
// queued at Stop are dropped (their requests are answered by the server as it stops).
// Thread-safe.
#ifndef ISPQ_SERVER_HTTP_HANDLER_POOL_H_
#define ISPQ_SERVER_HTTP_HANDLER_POOL_H_

#include <deque>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"

namespace ispq::server::http {

class HandlerPool {
 public:
  // Starts `threads` threads named `name` (in ps and debuggers).
  HandlerPool(int threads, std::string name);
  ~HandlerPool();
  HandlerPool(const HandlerPool&) = delete;
  HandlerPool& operator=(const HandlerPool&) = delete;

  // Queues `task`; false (and `task` dropped) once stopping.
  bool Post(std::function<void()> task);
  // Drops the queued tasks, waits for the running ones and joins the threads. Idempotent.
  void Stop();

 private:
  void Run();

  absl::Mutex mutex_;
  std::deque<std::function<void()>> tasks_ ABSL_GUARDED_BY(mutex_);
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  std::vector<std::thread> threads_;
};

}  // namespace ispq::server::http

#endif  // ISPQ_SERVER_HTTP_HANDLER_POOL_H_
