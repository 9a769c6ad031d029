// SPDX-License-Identifier: Apache-2.0
// The upstream research implementation's results on the real T-meshes
// (tests/data/reference/qgp3d-isp.tsv and qgp3d-iqp-all.tsv), keyed by model and level, so the
// benchmark can report ratios against them.
#ifndef ISPQ_TESTS_BENCH_REFERENCE_RESULTS_H_
#define ISPQ_TESTS_BENCH_REFERENCE_RESULTS_H_

#include <map>
#include <optional>
#include <string>
#include <utility>

namespace ispq::bench {

struct ReferenceRun {
  double seconds = 0;
  double objective = 0;
  bool valid = false;
};

class ReferenceResults {
 public:
  // Reads both files from `dir`; missing files leave the tables empty.
  static ReferenceResults Load(const std::string& dir);

  // Keys are "<dataset>/<model>" and the level percent.
  std::optional<ReferenceRun> Isp(const std::string& model, int percent) const;
  std::optional<ReferenceRun> Iqp(const std::string& model, int percent) const;
  int isp_runs() const { return static_cast<int>(isp_.size()); }

 private:
  using Key = std::pair<std::string, int>;
  std::map<Key, ReferenceRun> isp_;
  std::map<Key, ReferenceRun> iqp_;
};

}  // namespace ispq::bench

#endif  // ISPQ_TESTS_BENCH_REFERENCE_RESULTS_H_
