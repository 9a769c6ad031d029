// SPDX-License-Identifier: Apache-2.0
#include "tests/support/heap_peak.h"

#include <malloc.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdlib>

// glibc's own implementations, which the replacements below forward to.
extern "C" {
void* __libc_malloc(size_t size);
void __libc_free(void* pointer);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* pointer, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void* __libc_valloc(size_t size);
void* __libc_pvalloc(size_t size);
}

namespace {

// Constant-initialized, so usable by allocations made before any constructor runs.
std::atomic<int64_t> live_bytes{0};
std::atomic<int64_t> peak_bytes{0};

void Allocated(void* pointer) {
  if (pointer == nullptr) return;
  const auto size = static_cast<int64_t>(malloc_usable_size(pointer));
  const int64_t now = live_bytes.fetch_add(size, std::memory_order_relaxed) + size;
  int64_t peak = peak_bytes.load(std::memory_order_relaxed);
  while (now > peak && !peak_bytes.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {
  }
}

void Freed(void* pointer) {
  if (pointer == nullptr) return;
  live_bytes.fetch_sub(static_cast<int64_t>(malloc_usable_size(pointer)),
                       std::memory_order_relaxed);
}

}  // namespace

extern "C" {

void* malloc(size_t size) {
  void* pointer = __libc_malloc(size);
  Allocated(pointer);
  return pointer;
}

void free(void* pointer) {
  Freed(pointer);
  __libc_free(pointer);
}

void* calloc(size_t count, size_t size) {
  void* pointer = __libc_calloc(count, size);
  Allocated(pointer);
  return pointer;
}

void* realloc(void* pointer, size_t size) {
  const int64_t before = pointer != nullptr ? static_cast<int64_t>(malloc_usable_size(pointer)) : 0;
  void* moved = __libc_realloc(pointer, size);
  if (moved == nullptr && size != 0) return nullptr;  // the old block is untouched
  live_bytes.fetch_sub(before, std::memory_order_relaxed);
  Allocated(moved);
  return moved;
}

void* memalign(size_t alignment, size_t size) {
  void* pointer = __libc_memalign(alignment, size);
  Allocated(pointer);
  return pointer;
}

void* aligned_alloc(size_t alignment, size_t size) { return memalign(alignment, size); }

int posix_memalign(void** result, size_t alignment, size_t size) {
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0) return EINVAL;
  void* pointer = memalign(alignment, size);
  if (pointer == nullptr) return ENOMEM;
  *result = pointer;
  return 0;
}

void* valloc(size_t size) {
  void* pointer = __libc_valloc(size);
  Allocated(pointer);
  return pointer;
}

void* pvalloc(size_t size) {
  void* pointer = __libc_pvalloc(size);
  Allocated(pointer);
  return pointer;
}

}  // extern "C"

namespace ispq::testing {

bool HeapCountingActive() {
  const int64_t before = LiveHeapBytes();
  void* volatile probe = std::malloc(4096);
  const bool counted = LiveHeapBytes() >= before + 4096;
  std::free(probe);
  return counted;
}

int64_t LiveHeapBytes() { return live_bytes.load(std::memory_order_relaxed); }

HeapPeakScope::HeapPeakScope() : baseline_(LiveHeapBytes()) {
  peak_bytes.store(baseline_, std::memory_order_relaxed);
}

int64_t HeapPeakScope::PeakBytes() const {
  const int64_t peak = peak_bytes.load(std::memory_order_relaxed) - baseline_;
  return peak > 0 ? peak : 0;
}

}  // namespace ispq::testing
