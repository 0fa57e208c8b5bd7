// Progress of a long command (eval, bench-track, record) for a person at a terminal: one line on
// stderr, redrawn in place, with what is done and an estimate of the time left. Nothing at all
// when stderr is not a terminal (a log, a pipe, CI), so logs stay plain.
#pragma once

#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>

namespace saccade {

class ProgressLine {
 public:
  /// Draws on `err` only when `terminal` (ProgressLine::ForStderr decides it for std::cerr).
  ProgressLine(std::ostream& err, bool terminal) : err_(err), terminal_(terminal) {}
  ~ProgressLine() { Clear(); }
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  /// Whether stderr is a terminal.
  static bool StderrIsATerminal();

  /// `done` of `total` (0: not known) of `what`; the clock of its estimate starts at the first Show
  /// of a new `what`. Redrawn at most 5 times a second, and always at the last step.
  void Show(const std::string& what, std::size_t done, std::size_t total);
  /// Erases the line, so that a plain line printed next starts clean.
  void Clear();

  /// The line itself: "WHAT: 37/212 (17%), 2:13 left" ("..., 0:00 left" at the end; no
  /// estimate before the first step is done); with `total` 0 (not known), "WHAT: 37 done".
  static std::string Text(const std::string& what, std::size_t done, std::size_t total,
                          double elapsed_s);

 private:
  using Clock = std::chrono::steady_clock;
  std::ostream& err_;
  const bool terminal_;
  std::string what_;
  Clock::time_point started_{}, drawn_{};
  std::size_t width_ = 0;  // of the line on screen
};

}  // namespace saccade
