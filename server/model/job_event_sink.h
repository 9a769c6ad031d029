// SPDX-License-Identifier: Apache-2.0
// Where a job reports what happens to it so that it outlives the process: a durable job store
// (server/store/postgres/postgres_job_store.h) records every state change and event of the jobs
// this replica creates or runs, so that every replica can answer about them and watch them.
//
// The in-memory store needs none: it holds the job objects themselves.
#ifndef ISPQ_SERVER_MODEL_JOB_EVENT_SINK_H_
#define ISPQ_SERVER_MODEL_JOB_EVENT_SINK_H_

#include "ispq/v1/service.pb.h"

namespace ispq::server {

class Job;

class JobEventSink {
 public:
  virtual ~JobEventSink() = default;
  // Called after `job` changed, with none of its locks held: `event` is the event it just
  // emitted, or null when only its state changed (it started). Runs on the thread that changed
  // the job, often the worker inside the solver's progress callback: it must not wait for the
  // store (the database may be slow or down), only note what is to be written. A sink that
  // finds the job is no longer this replica's to record (its lease passed to another replica)
  // abandons the run (Job::Abandon).
  virtual void Record(Job& job, const v1::QuantizeEvent* event) = 0;
};

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MODEL_JOB_EVENT_SINK_H_
