// SPDX-License-Identifier: Apache-2.0
// Drops stalled uploads: a streamed upload (server/grpc/mesh_upload.h) holds memory for the size
// it declared from its first message on, so a client that stops sending (or goes away without
// closing its stream) would keep that memory forever. Every call the watchdog watches and that
// has not been touched for the idle limit is cancelled (TryCancel), which ends it and lets its
// reactor release what it holds. One thread checks the watched calls a few times per second.
#ifndef ISPQ_SERVER_GRPC_UPLOAD_WATCHDOG_H_
#define ISPQ_SERVER_GRPC_UPLOAD_WATCHDOG_H_

#include <cstdint>
#include <thread>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "grpcpp/server_context.h"

namespace ispq::server {

class UploadWatchdog {
 public:
  explicit UploadWatchdog(absl::Duration idle_limit);
  ~UploadWatchdog();  // stops its thread; every watched call must have been forgotten
  UploadWatchdog(const UploadWatchdog&) = delete;
  UploadWatchdog& operator=(const UploadWatchdog&) = delete;

  absl::Duration idle_limit() const { return idle_limit_; }

  // Watches `context` from now on (touched now).
  void Watch(grpc::CallbackServerContext* context);
  // The call made progress: its idle time starts again.
  void Touch(grpc::CallbackServerContext* context);
  // Stops watching `context`; call before the call is done. Whether the watchdog cancelled it.
  bool Forget(grpc::CallbackServerContext* context);
  // Calls cancelled for being idle since the server started.
  int64_t dropped() const;

 private:
  void CheckUntilStopped();

  const absl::Duration idle_limit_;
  mutable absl::Mutex mutex_;
  // Watched calls: when each last made progress, and whether it was cancelled.
  struct Watched {
    absl::Time touched;
    bool cancelled = false;
  };
  absl::flat_hash_map<grpc::CallbackServerContext*, Watched> watched_ ABSL_GUARDED_BY(mutex_);
  int64_t dropped_ ABSL_GUARDED_BY(mutex_) = 0;
  bool stopping_ ABSL_GUARDED_BY(mutex_) = false;
  std::thread checker_;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_GRPC_UPLOAD_WATCHDOG_H_
