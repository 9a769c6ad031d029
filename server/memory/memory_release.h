// SPDX-License-Identifier: Apache-2.0
// Giving freed heap memory back to the operating system after large, short-lived allocations
// (a job's solve, a large request's parse).
//
// glibc keeps freed memory in its arenas and returns only the free top of each heap, so after a
// solve that allocated and freed tens of megabytes in many blocks, the pages stay resident:
// measured on 110 jobs of 14k arcs one after another, the server's resident set grew by about
// 13 MB per job to 1.7 GB while the heap in use stayed below 10 MB, and the memory budget, which
// accounts what is in use, could not see it. malloc_trim releases the free pages inside the heaps
// too; it costs about 10 ms after such a job and 0.1 ms after a small one. (Blocks of 128 KiB or
// more have mappings of their own, which leave with their free: core/large_allocations.h.)
#ifndef ISPQ_SERVER_MEMORY_MEMORY_RELEASE_H_
#define ISPQ_SERVER_MEMORY_MEMORY_RELEASE_H_

namespace ispq::server {

// Returns the free pages of every malloc arena to the system. Thread-safe.
void ReleaseFreedMemory();

}  // namespace ispq::server

#endif  // ISPQ_SERVER_MEMORY_MEMORY_RELEASE_H_
