// SPDX-License-Identifier: Apache-2.0
// The events of one job, numbered in the order the job emitted them, kept so that a watcher can
// (re)join at any event number.
//
// Memory stays bounded however long a job runs: progress and intermediate quantizations are
// snapshots, so appending one drops the previous event of the same kind. What is kept is at
// most four events: the accepted event, the latest progress, the latest intermediate
// quantization and the terminal event (result or error); the terminal event also drops the
// intermediate quantization, which the result supersedes. A reader asking for event n gets the
// first kept event numbered n or more; numbers only increase along a stream, with gaps where
// snapshots were superseded. Not thread-safe: the owning Job guards it.
#ifndef ISPQ_SERVER_MODEL_JOB_EVENT_LOG_H_
#define ISPQ_SERVER_MODEL_JOB_EVENT_LOG_H_

#include <cstdint>
#include <vector>

#include "ispq/v1/service.pb.h"

namespace ispq::server {

class JobEventLog {
 public:
  // Numbers `event` (its `sequence` field is overwritten), keeps it and returns its number.
  int64_t Append(v1::QuantizeEvent event);

  // The first kept event numbered at least `from`, or nullptr if there is none yet.
  const v1::QuantizeEvent* FirstAtOrAfter(int64_t from) const;

  // The number the next event will get: how many events were emitted so far.
  int64_t emitted() const { return next_sequence_; }

  // Whether the last event was terminal (a result or an error).
  bool ended() const;

  // Replaces everything with events read back from a store (server/store/job_store.h): `kept` in
  // increasing sequence order, `emitted` the number the next event would get.
  void Restore(std::vector<v1::QuantizeEvent> kept, int64_t emitted);
  // Numbers the next events from `next_sequence` on: a job run again after its first run was
  // lost continues the numbering its watchers have seen.
  void ContinueFrom(int64_t next_sequence) { next_sequence_ = next_sequence; }

 private:
  std::vector<v1::QuantizeEvent> kept_;  // increasing sequence numbers
  int64_t next_sequence_ = 0;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MODEL_JOB_EVENT_LOG_H_
