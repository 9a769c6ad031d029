// SPDX-License-Identifier: Apache-2.0
// Linked into every executable of the `tsan` preset (CMakeLists.txt, ISPQ_TSAN): tells
// ThreadSanitizer about absl::Mutex, absl::CondVar and absl::Notification.
//
// Debian's abseil is not built with -fsanitize=thread, so its Mutex carries none of the
// __tsan_mutex_* annotations that an instrumented abseil has, and its atomics are invisible:
// without this file TSan sees no happens-before edge from any absl::Mutex, and reports a race
// on every member guarded by one. This file defines the public lock and unlock functions of
// absl::Mutex and absl::CondVar in the executable, which comes first in symbol lookup, so that
// every call to them (ours, and those of gRPC and of abseil itself, through the PLT) comes here:
// each annotates the operation for TSan (as an instrumented abseil does) and calls abseil's own
// definition (dlsym RTLD_NEXT).
//
// Inside the real call TSan ignores memory accesses (between __tsan_mutex_pre_* and post_*):
// abseil evaluates the Conditions of Await and LockWhen there, sometimes in another thread
// than the waiter's, while holding the lock, which TSan cannot see. The Conditions read only,
// under the lock, so nothing is lost but races inside a Condition itself.
//
// Reader locks are annotated as such; Await and CondVar::Wait are assumed to be called with
// the lock held exclusively (ispq never awaits under a reader lock).
#include <dlfcn.h>
#include <sanitizer/tsan_interface.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "absl/base/options.h"
#include "absl/synchronization/mutex.h"
#include "absl/synchronization/notification.h"
#include "absl/time/time.h"

#if defined(__clang__)
#if !__has_feature(thread_sanitizer)
#error "only for -fsanitize=thread builds (the tsan preset)"
#endif
#elif !defined(__SANITIZE_THREAD__)
#error "only for -fsanitize=thread builds (the tsan preset)"
#endif

// The mangled names below are those of Debian 12's abseil (inline namespace debian3).
#define ISPQ_STRINGIFY_(x) #x
#define ISPQ_STRINGIFY(x) ISPQ_STRINGIFY_(x)
static_assert(std::string_view(ISPQ_STRINGIFY(ABSL_OPTION_INLINE_NAMESPACE_NAME)) == "debian3",
              "another abseil: update the mangled names of absl_sync_annotations.cc");

namespace {

template <typename Function>
Function Real(const char* mangled) {
  void* real = dlsym(RTLD_NEXT, mangled);
  if (real == nullptr) {
    std::fprintf(stderr, "absl_sync_annotations: no %s in the libraries: %s\n", mangled, dlerror());
    std::abort();
  }
  return reinterpret_cast<Function>(real);
}

#define ISPQ_REAL(type, mangled)                \
  static const auto real = Real<type>(mangled); \
  (void)0

constexpr unsigned kRead = __tsan_mutex_read_lock;
constexpr unsigned kTry = __tsan_mutex_try_lock;
constexpr unsigned kTryFailed = __tsan_mutex_try_lock_failed;

// abseil's functions call one another through the PLT, hence through this file (e.g.
// AwaitWithTimeout calls AwaitWithDeadline, Notification's calls LockWhen): only the outermost
// call of a thread is annotated.
thread_local int nesting = 0;

struct Nested {
  Nested() { ++nesting; }
  ~Nested() { --nesting; }
};

template <typename Call>
auto Acquiring(void* mutex, unsigned flags, Call call) {
  if (nesting > 0) return call();
  __tsan_mutex_pre_lock(mutex, flags);
  auto result = [&] {
    Nested nested;
    return call();
  }();
  __tsan_mutex_post_lock(mutex, flags, 0);
  return result;
}

template <typename Call>
void Releasing(void* mutex, unsigned flags, Call call) {
  if (nesting > 0) return call();
  __tsan_mutex_pre_unlock(mutex, flags);
  {
    Nested nested;
    call();
  }
  __tsan_mutex_post_unlock(mutex, flags);
}

// Lock held exclusively on entry, released and held again on return (Await, CondVar::Wait).
template <typename Call>
auto ReleasedDuring(void* mutex, Call call) {
  if (nesting > 0) return call();
  __tsan_mutex_pre_unlock(mutex, 0);
  auto result = [&] {
    Nested nested;
    return call();
  }();
  __tsan_mutex_post_unlock(mutex, 0);
  __tsan_mutex_pre_lock(mutex, 0);
  __tsan_mutex_post_lock(mutex, 0, 0);
  return result;
}

bool TryAcquiring(void* mutex, unsigned flags, bool (*real)(absl::Mutex*), absl::Mutex* self) {
  if (nesting > 0) return real(self);
  __tsan_mutex_pre_lock(mutex, flags | kTry);
  bool locked;
  {
    Nested nested;
    locked = real(self);
  }
  __tsan_mutex_post_lock(mutex, flags | kTry | (locked ? 0 : kTryFailed), 0);
  return locked;
}

// absl::Notification as Debian 12's abseil lays it out: a Mutex, then the flag that Notify sets
// (under the mutex) and that waiters read with an acquire load.
struct NotificationLayout {
  absl::Mutex mutex;
  std::atomic<bool> notified_yet;
};
static_assert(sizeof(NotificationLayout) == sizeof(absl::Notification) &&
                  alignof(NotificationLayout) == alignof(absl::Notification),
              "another absl::Notification: update absl_sync_annotations.cc");

void* FlagOf(const absl::Notification* notification) {
  return &reinterpret_cast<NotificationLayout*>(const_cast<absl::Notification*>(notification))
              ->notified_yet;
}

// A wait on `notification` that returns `notified` true has seen Notify's release on the flag.
bool AcquireIfNotified(const absl::Notification* notification, bool notified) {
  if (notified) __tsan_acquire(FlagOf(notification));
  return notified;
}

}  // namespace

namespace absl {
ABSL_NAMESPACE_BEGIN

using Plain = void (*)(Mutex*);
using Try = bool (*)(Mutex*);
using When = void (*)(Mutex*, const Condition&);
using WhenTimeout = bool (*)(Mutex*, const Condition&, Duration);
using WhenDeadline = bool (*)(Mutex*, const Condition&, Time);

void Mutex::Lock() {
  ISPQ_REAL(Plain, "_ZN4absl7debian35Mutex4LockEv");
  Acquiring(this, 0, [&] { return real(this), 0; });
}

void Mutex::ReaderLock() {
  ISPQ_REAL(Plain, "_ZN4absl7debian35Mutex10ReaderLockEv");
  Acquiring(this, kRead, [&] { return real(this), 0; });
}

void Mutex::Unlock() {
  ISPQ_REAL(Plain, "_ZN4absl7debian35Mutex6UnlockEv");
  Releasing(this, 0, [&] { real(this); });
}

void Mutex::ReaderUnlock() {
  ISPQ_REAL(Plain, "_ZN4absl7debian35Mutex12ReaderUnlockEv");
  Releasing(this, kRead, [&] { real(this); });
}

bool Mutex::TryLock() {
  ISPQ_REAL(Try, "_ZN4absl7debian35Mutex7TryLockEv");
  return TryAcquiring(this, 0, real, this);
}

bool Mutex::ReaderTryLock() {
  ISPQ_REAL(Try, "_ZN4absl7debian35Mutex13ReaderTryLockEv");
  return TryAcquiring(this, kRead, real, this);
}

void Mutex::LockWhen(const Condition& cond) {
  ISPQ_REAL(When, "_ZN4absl7debian35Mutex8LockWhenERKNS0_9ConditionE");
  Acquiring(this, 0, [&] { return real(this, cond), 0; });
}

void Mutex::ReaderLockWhen(const Condition& cond) {
  ISPQ_REAL(When, "_ZN4absl7debian35Mutex14ReaderLockWhenERKNS0_9ConditionE");
  Acquiring(this, kRead, [&] { return real(this, cond), 0; });
}

bool Mutex::LockWhenWithTimeout(const Condition& cond, Duration timeout) {
  ISPQ_REAL(WhenTimeout,
            "_ZN4absl7debian35Mutex19LockWhenWithTimeoutERKNS0_9ConditionENS0_8DurationE");
  return Acquiring(this, 0, [&] { return real(this, cond, timeout); });
}

bool Mutex::ReaderLockWhenWithTimeout(const Condition& cond, Duration timeout) {
  ISPQ_REAL(WhenTimeout,
            "_ZN4absl7debian35Mutex25ReaderLockWhenWithTimeoutERKNS0_9ConditionENS0_8DurationE");
  return Acquiring(this, kRead, [&] { return real(this, cond, timeout); });
}

bool Mutex::LockWhenWithDeadline(const Condition& cond, Time deadline) {
  ISPQ_REAL(WhenDeadline,
            "_ZN4absl7debian35Mutex20LockWhenWithDeadlineERKNS0_9ConditionENS0_4TimeE");
  return Acquiring(this, 0, [&] { return real(this, cond, deadline); });
}

bool Mutex::ReaderLockWhenWithDeadline(const Condition& cond, Time deadline) {
  ISPQ_REAL(WhenDeadline,
            "_ZN4absl7debian35Mutex26ReaderLockWhenWithDeadlineERKNS0_9ConditionENS0_4TimeE");
  return Acquiring(this, kRead, [&] { return real(this, cond, deadline); });
}

void Mutex::Await(const Condition& cond) {
  ISPQ_REAL(When, "_ZN4absl7debian35Mutex5AwaitERKNS0_9ConditionE");
  ReleasedDuring(this, [&] { return real(this, cond), 0; });
}

bool Mutex::AwaitWithTimeout(const Condition& cond, Duration timeout) {
  ISPQ_REAL(WhenTimeout,
            "_ZN4absl7debian35Mutex16AwaitWithTimeoutERKNS0_9ConditionENS0_8DurationE");
  return ReleasedDuring(this, [&] { return real(this, cond, timeout); });
}

bool Mutex::AwaitWithDeadline(const Condition& cond, Time deadline) {
  ISPQ_REAL(WhenDeadline, "_ZN4absl7debian35Mutex17AwaitWithDeadlineERKNS0_9ConditionENS0_4TimeE");
  return ReleasedDuring(this, [&] { return real(this, cond, deadline); });
}

void CondVar::Wait(Mutex* mu) {
  using Function = void (*)(CondVar*, Mutex*);
  ISPQ_REAL(Function, "_ZN4absl7debian37CondVar4WaitEPNS0_5MutexE");
  ReleasedDuring(mu, [&] { return real(this, mu), 0; });
}

bool CondVar::WaitWithTimeout(Mutex* mu, Duration timeout) {
  using Function = bool (*)(CondVar*, Mutex*, Duration);
  ISPQ_REAL(Function, "_ZN4absl7debian37CondVar15WaitWithTimeoutEPNS0_5MutexENS0_8DurationE");
  return ReleasedDuring(mu, [&] { return real(this, mu, timeout); });
}

bool CondVar::WaitWithDeadline(Mutex* mu, Time deadline) {
  using Function = bool (*)(CondVar*, Mutex*, Time);
  ISPQ_REAL(Function, "_ZN4absl7debian37CondVar16WaitWithDeadlineEPNS0_5MutexENS0_4TimeE");
  return ReleasedDuring(mu, [&] { return real(this, mu, deadline); });
}

// A waiter that finds the flag already set takes no lock: WaitForNotification* return at once
// from inside abseil, and the inline HasBeenNotified() loads the flag in our own code, so TSan
// saw no edge from the notifier's writes to the waiter's reads (HandlerPoolTest.NamesItsThreads
// reported one, once: the task had notified before the test began to wait). Notify releases on
// the flag's address, which the instrumented acquire load of HasBeenNotified() pairs with; a wait
// that returns true acquires on it.
using NotifyFunction = void (*)(Notification*);
using WaitFunction = void (*)(const Notification*);
using WaitTimeoutFunction = bool (*)(const Notification*, Duration);
using WaitDeadlineFunction = bool (*)(const Notification*, Time);

void Notification::Notify() {
  ISPQ_REAL(NotifyFunction, "_ZN4absl7debian312Notification6NotifyEv");
  __tsan_release(FlagOf(this));
  real(this);
}

void Notification::WaitForNotification() const {
  ISPQ_REAL(WaitFunction, "_ZNK4absl7debian312Notification19WaitForNotificationEv");
  real(this);
  AcquireIfNotified(this, true);
}

bool Notification::WaitForNotificationWithTimeout(Duration timeout) const {
  ISPQ_REAL(WaitTimeoutFunction,
            "_ZNK4absl7debian312Notification30WaitForNotificationWithTimeoutENS0_8DurationE");
  return AcquireIfNotified(this, real(this, timeout));
}

bool Notification::WaitForNotificationWithDeadline(Time deadline) const {
  ISPQ_REAL(WaitDeadlineFunction,
            "_ZNK4absl7debian312Notification31WaitForNotificationWithDeadlineENS0_4TimeE");
  return AcquireIfNotified(this, real(this, deadline));
}

ABSL_NAMESPACE_END
}  // namespace absl
