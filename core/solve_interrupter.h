// SPDX-License-Identifier: Apache-2.0
// Cooperative cancellation of a running quantization. The owner calls Interrupt() from any
// thread; the algorithm polls IsInterrupted() between LP solves and stops at the next check,
// returning the best valid quantization found so far. Thread-safe.
#ifndef ISPQ_CORE_SOLVE_INTERRUPTER_H_
#define ISPQ_CORE_SOLVE_INTERRUPTER_H_

#include <atomic>

namespace ispq {

class SolveInterrupter {
 public:
  SolveInterrupter() = default;
  SolveInterrupter(const SolveInterrupter&) = delete;
  SolveInterrupter& operator=(const SolveInterrupter&) = delete;

  void Interrupt() { interrupted_.store(true, std::memory_order_release); }
  bool IsInterrupted() const { return interrupted_.load(std::memory_order_acquire); }

 private:
  std::atomic<bool> interrupted_{false};
};

}  // namespace ispq

#endif  // ISPQ_CORE_SOLVE_INTERRUPTER_H_
