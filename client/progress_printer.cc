// SPDX-License-Identifier: Apache-2.0
#include "client/progress_printer.h"

#include <unistd.h>

#include <algorithm>

namespace ispq::cli {
namespace {

// Plain (non-TTY) output prints at most one line per this many seconds, plus phase changes.
constexpr double kPlainLineInterval = 0.5;

const char* PhaseLabel(v1::Phase phase) {
  switch (phase) {
    case v1::GREEDY:
      return "greedy";
    case v1::SEPARATION:
      return "separation";
    case v1::FAILSAFE:
      return "failsafe";
    case v1::FINAL:
      return "final";
    case v1::EXACT:
      return "exact";
    case v1::LAYERS:
      return "layers";
    default:
      return "starting";
  }
}

}  // namespace

ProgressPrinter::ProgressPrinter(FILE* out) : out_(out), tty_(isatty(fileno(out)) != 0) {}

void ProgressPrinter::Update(const v1::Progress& p) {
  if (p.phase() == v1::EXACT) {
    UpdateExact(p);
    return;
  }
  if (tty_) {
    std::fprintf(
        out_,
        "\r\033[K%-10s sheets %-6lld round %-3lld objective %-12.4f violated %-4lld %s %7.2fs",
        PhaseLabel(p.phase()), static_cast<long long>(p.iteration()),
        static_cast<long long>(p.separation_round()), p.objective(),
        static_cast<long long>(p.violated_constraints()),
        p.separating() ? "separating    " : "not separating", p.elapsed_seconds());
    line_open_ = true;
  } else {
    if (last_plain_seconds_ >= 0 &&
        p.elapsed_seconds() - last_plain_seconds_ < kPlainLineInterval) {
      return;
    }
    last_plain_seconds_ = p.elapsed_seconds();
    std::fprintf(out_,
                 "progress phase=%s sheets=%lld round=%lld objective=%.6f violated=%lld "
                 "separating=%s elapsed=%.3fs\n",
                 PhaseLabel(p.phase()), static_cast<long long>(p.iteration()),
                 static_cast<long long>(p.separation_round()), p.objective(),
                 static_cast<long long>(p.violated_constraints()), p.separating() ? "yes" : "no",
                 p.elapsed_seconds());
  }
  std::fflush(out_);
}

void ProgressPrinter::UpdateExact(const v1::Progress& p) {
  const double gap = p.objective() > 0 && p.has_lower_bound()
                         ? 100 * std::max(0.0, p.objective() - p.lower_bound()) / p.objective()
                         : 0;
  if (tty_) {
    std::fprintf(out_,
                 "\r\033[K%-10s nodes %-7lld solve %-3lld objective %-12.4f bound %-12.4f gap "
                 "%6.2f%% %7.2fs",
                 "exact", static_cast<long long>(p.iteration()),
                 static_cast<long long>(p.separation_round()), p.objective(), p.lower_bound(), gap,
                 p.elapsed_seconds());
    line_open_ = true;
  } else {
    // The first exact line marks the change of phase; later ones are throttled.
    if (exact_line_printed_ && p.elapsed_seconds() - last_plain_seconds_ < kPlainLineInterval) {
      return;
    }
    exact_line_printed_ = true;
    last_plain_seconds_ = p.elapsed_seconds();
    std::fprintf(out_,
                 "progress phase=exact nodes=%lld solves=%lld objective=%.6f bound=%.6f "
                 "gap=%.4f%% elapsed=%.3fs\n",
                 static_cast<long long>(p.iteration()),
                 static_cast<long long>(p.separation_round()), p.objective(), p.lower_bound(), gap,
                 p.elapsed_seconds());
  }
  std::fflush(out_);
}

void ProgressPrinter::Finish() {
  if (line_open_) std::fputc('\n', out_);
  line_open_ = false;
  std::fflush(out_);
}

}  // namespace ispq::cli
