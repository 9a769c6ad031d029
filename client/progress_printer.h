// SPDX-License-Identifier: Apache-2.0
// Live progress of a quantization on the terminal, fed with ispq.v1.Progress messages from either
// an in-process run or a server's event stream. On a TTY one status line is redrawn in place;
// otherwise each update is a plain line, throttled so logs stay readable.
#ifndef ISPQ_CLIENT_PROGRESS_PRINTER_H_
#define ISPQ_CLIENT_PROGRESS_PRINTER_H_

#include <cstdio>

#include "ispq/v1/quantization.pb.h"

namespace ispq::cli {

class ProgressPrinter {
 public:
  // Writes to `out` (normally stderr, so that stdout carries only results).
  explicit ProgressPrinter(FILE* out);

  void Update(const v1::Progress& progress);
  // Ends the status line (TTY) so that following output starts on a fresh line.
  void Finish();

 private:
  // Exact mode's phase: nodes, MILP solves, the best objective, the bound and the gap.
  void UpdateExact(const v1::Progress& progress);

  FILE* out_;
  bool tty_;
  bool line_open_ = false;
  double last_plain_seconds_ = -1;
  bool exact_line_printed_ = false;
};

}  // namespace ispq::cli

#endif  // ISPQ_CLIENT_PROGRESS_PRINTER_H_
