// SPDX-License-Identifier: Apache-2.0
// CPU priority of the server's own long-running threads (solver workers, admission threads).
//
// They are CPU-bound for seconds at a time; gRPC's threads answer calls, health probes among
// them, in microseconds. At equal priority the kernel shares a loaded machine's cores evenly
// between them, and a probe waits its turn behind the solves (measured on 2 shared cores: health
// probes taking over 100 ms during a burst of large requests). Lower priority for the CPU-bound
// threads lets gRPC's threads run first whenever they are ready, at no cost to throughput when
// they are idle.
#ifndef ISPQ_SERVER_JOBS_THREAD_PRIORITY_H_
#define ISPQ_SERVER_JOBS_THREAD_PRIORITY_H_

namespace ispq::server {

// Lowers the calling thread's scheduling priority (nice +10). Best effort: if the system
// refuses, the thread keeps its priority.
void LowerCurrentThreadPriority();

}  // namespace ispq::server

#endif  // ISPQ_SERVER_JOBS_THREAD_PRIORITY_H_
