#include "daemon/cli/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace saccade {

bool ProgressLine::StderrIsATerminal() { return isatty(STDERR_FILENO) == 1; }

std::string ProgressLine::Text(const std::string& what, std::size_t done, std::size_t total,
                               double elapsed_s) {
  char line[96];
  if (total == 0) {  // a count without an end: no share, no estimate
    std::snprintf(line, sizeof line, ": %zu done", done);
    return what + line;
  }
  std::snprintf(line, sizeof line, ": %zu/%zu (%.0f%%)", done, total,
                100.0 * double(done) / double(total));
  std::string text = what + line;
  if (done == 0) return text;
  const long left = std::lround(elapsed_s / double(done) * double(total - std::min(done, total)));
  if (left >= 3600)
    std::snprintf(line, sizeof line, ", %ld:%02ld:%02ld left", left / 3600, left / 60 % 60,
                  left % 60);
  else
    std::snprintf(line, sizeof line, ", %ld:%02ld left", left / 60, left % 60);
  return text + line;
}

void ProgressLine::Show(const std::string& what, std::size_t done, std::size_t total) {
  if (!terminal_) return;
  const Clock::time_point now = Clock::now();
  if (what != what_) what_ = what, started_ = now, drawn_ = {};
  if (done < total && now - drawn_ < std::chrono::milliseconds(200)) return;
  drawn_ = now;
  const std::string text =
      Text(what, done, total, std::chrono::duration<double>(now - started_).count());
  // Spaces over what is left of a longer line before it.
  err_ << '\r' << text << std::string(width_ > text.size() ? width_ - text.size() : 0, ' ')
       << std::flush;
  width_ = text.size();
}

void ProgressLine::Clear() {
  if (!terminal_ || width_ == 0) return;
  err_ << '\r' << std::string(width_, ' ') << '\r' << std::flush;
  width_ = 0;
}

}  // namespace saccade
