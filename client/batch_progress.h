// SPDX-License-Identifier: Apache-2.0
// What `ispq batch` shows while it runs, on stderr: a line per running job (its phase and
// objective, or why it waits) and a total line, redrawn in place on a terminal; a permanent line
// per finished job. Without a terminal only the permanent lines, notices (a retry, a resubmission)
// and the total after each finished job are written, so that logs stay readable. Thread-safe:
// each worker of the batch reports its own job.
#ifndef ISPQ_CLIENT_BATCH_PROGRESS_H_
#define ISPQ_CLIENT_BATCH_PROGRESS_H_

#include <cstdio>
#include <map>
#include <string>

#include "absl/base/thread_annotations.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"

namespace ispq::cli {

class BatchProgress {
 public:
  // `total` jobs; `enabled` false writes nothing (--progress=false).
  BatchProgress(FILE* out, int total, bool enabled);

  // The running job `index` is at `status` (redrawn on a terminal at most every 100 ms).
  void Update(int index, const std::string& name, const std::string& status);
  // Something the user should see even in a log: a retry, a resubmission.
  void Notice(int index, const std::string& name, const std::string& notice);
  // Job `index` ended: `ok` false counts it as failed.
  void Finished(int index, const std::string& name, bool ok, const std::string& outcome);
  // Clears the live lines before the summary.
  void Close();

 private:
  std::string TotalLine() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void PrintLine(const std::string& line) ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Erase() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);
  void Draw() ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex_);

  FILE* const out_;
  const int total_;
  const bool enabled_;
  const bool tty_;
  absl::Mutex mutex_;
  std::map<int, std::string> running_ ABSL_GUARDED_BY(mutex_);  // by job index: its line
  int succeeded_ ABSL_GUARDED_BY(mutex_) = 0;
  int failed_ ABSL_GUARDED_BY(mutex_) = 0;
  int drawn_lines_ ABSL_GUARDED_BY(mutex_) = 0;  // live lines on the terminal now
  absl::Time last_draw_ ABSL_GUARDED_BY(mutex_) = absl::InfinitePast();
};

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_BATCH_PROGRESS_H_
