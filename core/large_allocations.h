// SPDX-License-Identifier: Apache-2.0
// How a process that runs solves has its large blocks allocated: the server's and the CLI's
// main() call MapLargeAllocationsSeparately() before anything else, and so do the benchmarks
// that measure memory.
//
// glibc maps a block of 128 KiB or more on its own (when no free space in the heap can hold it)
// and unmaps it when it is freed, but once such a block is freed it raises that threshold to the
// freed block's size (up to 32 MiB). From then on a solve's larger blocks (vectors that grow by
// doubling, the copy of an LP handed to CLP, row batches, the loader's buffers) come from the
// heap, where the space they leave when freed stays resident and is reused only by blocks that
// fit into it. Fixing the threshold keeps them mapped and gives their memory back as soon as
// they are freed: the peak resident set of a solve of a 300k-arc assembly at level 5 fell from
// 652 to 518 MiB, at the cost of the page faults of fresh mappings (+1 to +11 % CPU; see
// tests/bench/large/results/assembly/README.md).
//
// Sanitizer builds replace malloc, and the call does nothing there.
#ifndef ISPQ_CORE_LARGE_ALLOCATIONS_H_
#define ISPQ_CORE_LARGE_ALLOCATIONS_H_

#include <cstddef>

namespace ispq {

// Blocks of at least this many bytes get a mapping of their own (glibc's initial threshold).
inline constexpr size_t kSeparateMappingMinBytes = 128 << 10;

// Fixes glibc's mmap threshold at kSeparateMappingMinBytes; false if malloc refused.
bool MapLargeAllocationsSeparately();

}  // namespace ispq

#endif  // ISPQ_CORE_LARGE_ALLOCATIONS_H_
