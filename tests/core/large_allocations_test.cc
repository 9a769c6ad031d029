// SPDX-License-Identifier: Apache-2.0
// MapLargeAllocationsSeparately (core/large_allocations.h): after a large mapped block is freed,
// a block of twice the threshold still gets a mapping of its own, which leaves with its free.
// Observed through glibc's count of mapped bytes; sanitizer builds bring their own malloc.
//
// The check runs in a fresh process (the death test's "threadsafe" style re-executes this
// binary for it): glibc maps a block only when no free block of the heap can serve it, and the
// tests before this one leave such blocks behind; the setting, process-wide and final, stays in
// that process too.
#include "core/large_allocations.h"

#include <malloc.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "gtest/gtest.h"
#include "tests/support/sanitizer_malloc.h"

namespace ispq {
namespace {

// Allocates, writes and frees `bytes`, so that the compiler cannot drop the pair.
void AllocateAndFree(size_t bytes) {
  char* volatile block = static_cast<char*>(malloc(bytes));
  if (block == nullptr) return;
  memset(block, 1, bytes);
  free(block);
}

// Exits with 0 if a block of twice the threshold was mapped and unmapped, else says what it saw.
[[noreturn]] void CheckMappingAfterALargeFree() {
  if (!MapLargeAllocationsSeparately()) {
    fprintf(stderr, "mallopt refused the threshold\n");
    _exit(1);
  }
  // Left to itself, glibc would now serve blocks of up to 16 MiB from the heap.
  AllocateAndFree(16 << 20);
  const size_t block_bytes = 2 * kSeparateMappingMinBytes;
  const size_t mapped_before = mallinfo2().hblkhd;
  char* volatile block = static_cast<char*>(malloc(block_bytes));
  const size_t mapped_with_block = mallinfo2().hblkhd;
  free(block);
  const size_t mapped_after = mallinfo2().hblkhd;
  if (mapped_with_block < mapped_before + block_bytes || mapped_after != mapped_before) {
    fprintf(stderr, "mapped bytes: %zu before, %zu with the block, %zu after its free\n",
            mapped_before, mapped_with_block, mapped_after);
    _exit(1);
  }
  _exit(0);
}

TEST(LargeAllocationsDeathTest, BlocksAboveTheThresholdStayMappedAfterALargerOneIsFreed) {
  if (testing::kSanitizerMalloc) GTEST_SKIP() << "malloc is the sanitizer's here";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(CheckMappingAfterALargeFree(), ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace ispq
