// SPDX-License-Identifier: Apache-2.0
#include "client/batch_progress.h"

#include <unistd.h>

#include "absl/strings/str_format.h"

namespace ispq::cli {

BatchProgress::BatchProgress(FILE* out, int total, bool enabled)
    : out_(out), total_(total), enabled_(enabled), tty_(isatty(fileno(out)) != 0) {}

void BatchProgress::Update(int index, const std::string& name, const std::string& status) {
  if (!enabled_) return;
  absl::MutexLock lock(&mutex_);
  running_[index] = absl::StrFormat("  %s: %s", name, status);
  if (tty_ && absl::Now() - last_draw_ >= absl::Milliseconds(100)) Draw();
}

void BatchProgress::Notice(int index, const std::string& name, const std::string& notice) {
  if (!enabled_) return;
  absl::MutexLock lock(&mutex_);
  running_[index] = absl::StrFormat("  %s: %s", name, notice);
  Erase();
  PrintLine(absl::StrFormat("%s: %s", name, notice));
  if (tty_) Draw();
}

void BatchProgress::Finished(int index, const std::string& name, bool ok,
                             const std::string& outcome) {
  absl::MutexLock lock(&mutex_);
  running_.erase(index);
  ++(ok ? succeeded_ : failed_);
  if (!enabled_) return;
  Erase();
  PrintLine(absl::StrFormat("%s %s: %s", ok ? "done  " : "FAILED", name, outcome));
  if (tty_) {
    Draw();
  } else {
    PrintLine(TotalLine());
  }
}

void BatchProgress::Close() {
  if (!enabled_) return;
  absl::MutexLock lock(&mutex_);
  Erase();
  std::fflush(out_);  // the summary may go to another stream
  running_.clear();
}

std::string BatchProgress::TotalLine() const {
  return absl::StrFormat("[%d/%d done, %d failed, %d running]", succeeded_ + failed_, total_,
                         failed_, static_cast<int>(running_.size()));
}

void BatchProgress::PrintLine(const std::string& line) {
  std::fprintf(out_, "%s\n", line.c_str());
  std::fflush(out_);
}

void BatchProgress::Erase() {
  for (; drawn_lines_ > 0; --drawn_lines_) std::fputs("\033[1A\033[2K", out_);
}

void BatchProgress::Draw() {
  Erase();
  for (const auto& [index, line] : running_) {
    std::fprintf(out_, "%s\n", line.c_str());
    ++drawn_lines_;
  }
  std::fprintf(out_, "%s\n", TotalLine().c_str());
  ++drawn_lines_;
  std::fflush(out_);
  last_draw_ = absl::Now();
}

}  // namespace ispq::cli
