// SPDX-License-Identifier: Apache-2.0
// The anytime curve of one run for the benchmark report (paper Figs. 10 and 11): every time the
// best valid objective or the proven lower bound improves, the time and both values. ISP reports
// a valid q whenever its last separation search came back empty (ProgressEvent::separating);
// exact mode's events always carry the best valid q and the bound.
#ifndef ISPQ_TESTS_BENCH_PROGRESS_TRACE_H_
#define ISPQ_TESTS_BENCH_PROGRESS_TRACE_H_

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/quantization_progress.h"

namespace ispq::bench {

struct TracePoint {
  double seconds;
  std::optional<double> objective;  // best valid so far
  std::optional<double> lower_bound;
};

class ProgressTrace : public ProgressObserver {
 public:
  void OnProgress(const ProgressEvent& event) override;
  const std::vector<TracePoint>& points() const { return points_; }

  // One TSV row per point: model, level, method, seconds, objective, lower_bound.
  void WriteRows(const std::string& model, int level, const std::string& method,
                 std::ostream& out) const;
  static void WriteHeader(std::ostream& out);

 private:
  std::optional<double> best_;
  std::optional<double> bound_;
  std::vector<TracePoint> points_;
};

}  // namespace ispq::bench

#endif  // ISPQ_TESTS_BENCH_PROGRESS_TRACE_H_
