// SPDX-License-Identifier: Apache-2.0
// ReleaseFreedMemory (server/memory/memory_release.h): memory a solve allocated in many small
// blocks and freed stays resident in glibc's heap while anything above it is still allocated;
// released, the process's resident set falls by it. Measured on the process's own resident set,
// with glibc's malloc (sanitizer builds bring their own allocator, where this is not observable).
#include "server/memory/memory_release.h"

#include <malloc.h>

#include <cstring>
#include <vector>

#include "gtest/gtest.h"
#include "tests/support/own_memory.h"
#include "tests/support/sanitizer_malloc.h"

namespace ispq::server {
namespace {

constexpr size_t kBlockBytes = 4 << 10;  // far below glibc's mmap threshold: on the heap
constexpr int kBlocks = 16384;           // 64 MiB

TEST(MemoryReleaseTest, FreedHeapPagesLeaveTheResidentSet) {
  if (testing::kSanitizerMalloc) GTEST_SKIP() << "malloc is the sanitizer's here";
  const size_t heap_before = mallinfo2().uordblks;
  std::vector<char*> blocks;
  blocks.reserve(kBlocks);
  for (int i = 0; i < kBlocks; ++i) {
    blocks.push_back(static_cast<char*>(malloc(kBlockBytes)));
    memset(blocks.back(), 1, kBlockBytes);  // resident
  }
  // The last block, allocated after the others at the heap's top, stays: freeing the others
  // leaves a hole below it, not a free heap top that free() would return by itself.
  char* const pin = blocks.back();
  blocks.pop_back();
  if (mallinfo2().uordblks < heap_before + kBlocks * kBlockBytes) {
    for (char* block : blocks) free(block);
    free(pin);
    GTEST_SKIP() << "malloc is not glibc's here";
  }
  for (char* block : blocks) free(block);
  const double resident_freed_kib = testing::OwnStatusKib("VmRSS:");

  ReleaseFreedMemory();
  const double resident_released_kib = testing::OwnStatusKib("VmRSS:");
  free(pin);
  const double block_kib = kBlocks * kBlockBytes / 1024.0;
  EXPECT_LE(resident_released_kib, resident_freed_kib - block_kib / 2)
      << "resident " << resident_freed_kib << " KiB after the free, " << resident_released_kib
      << " KiB after the release";
}

}  // namespace
}  // namespace ispq::server
