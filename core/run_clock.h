// SPDX-License-Identifier: Apache-2.0
// Time within one run, ISP or exact mode: the elapsed time for progress reports, the stop
// condition (the time limit or the caller's SolveInterrupter, checked between LP solves) and
// scoped timers that add a phase's CPU time to its statistic. Phases are timed in CPU time of the
// solving thread, which a busy machine does not inflate; the time limit and the reported elapsed
// time are wall time.
#ifndef ISPQ_CORE_RUN_CLOCK_H_
#define ISPQ_CORE_RUN_CLOCK_H_

#include <time.h>

#include <chrono>

#include "core/quantize_result.h"
#include "core/solve_interrupter.h"

namespace ispq {

class RunClock {
 public:
  using Clock = std::chrono::steady_clock;

  // `interrupter` may be null. The limit counts from `start` (by default: now).
  RunClock(const SolveInterrupter* interrupter, double time_limit_seconds,
           Clock::time_point start = Clock::now())
      : interrupter_(interrupter), time_limit_seconds_(time_limit_seconds), start_(start) {}

  double ElapsedSeconds() const { return SecondsSince(start_); }
  // Until the time limit (infinite without one; negative once it has passed).
  double RemainingSeconds() const { return time_limit_seconds_ - ElapsedSeconds(); }

  // Whether the run must stop; once true it stays true, and termination() says why.
  bool ShouldStop() {
    if (stopped_) return true;
    if (interrupter_ != nullptr && interrupter_->IsInterrupted()) {
      stopped_ = true;
      termination_ = Termination::kInterrupted;
    } else if (ElapsedSeconds() > time_limit_seconds_) {
      stopped_ = true;
      termination_ = Termination::kTimeLimit;
    }
    return stopped_;
  }
  // The last answer of ShouldStop, without checking again.
  bool stopped() const { return stopped_; }
  Termination termination() const { return stopped_ ? termination_ : Termination::kConverged; }

  static double SecondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  }

 private:
  const SolveInterrupter* interrupter_;
  const double time_limit_seconds_;
  const Clock::time_point start_;
  bool stopped_ = false;
  Termination termination_ = Termination::kConverged;
};

// CPU seconds the calling thread has used.
inline double ThreadCpuSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Adds the CPU time the thread spends in the scope to a statistic.
class ScopedCpuSeconds {
 public:
  explicit ScopedCpuSeconds(double* sink) : sink_(sink), start_(ThreadCpuSeconds()) {}
  ~ScopedCpuSeconds() { *sink_ += ThreadCpuSeconds() - start_; }
  ScopedCpuSeconds(const ScopedCpuSeconds&) = delete;
  ScopedCpuSeconds& operator=(const ScopedCpuSeconds&) = delete;

 private:
  double* sink_;
  double start_;
};

}  // namespace ispq

#endif  // ISPQ_CORE_RUN_CLOCK_H_
