// Leveled, line-at-a-time logging to stderr: "saccaded: warning: what (where)". Thread-safe.
#pragma once

#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace saccade {

enum class LogLevel { kDebug, kInfo, kWarning, kError };

/// Parses debug | info | warning | error.
bool ParseLogLevel(const std::string& name, LogLevel* level);
/// Process-wide settings: lines below `level` are dropped; `program` starts every line. When
/// stderr is journald's ($JOURNAL_STREAM), each line starts with its syslog priority ("<3>"),
/// so that `journalctl -p err` finds the errors.
void ConfigureLog(const std::string& program, LogLevel level);
void Log(LogLevel level, const std::string& message);
/// True when lines of `level` are written (to skip building a message nobody will see).
bool LogEnabled(LogLevel level);

/// Lets through at most `per_second` lines of one kind a second, so that a flood (bad commands,
/// a network that refuses every send) cannot flood the log. Thread-safe.
class LogLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  explicit LogLimiter(int per_second) : per_second_(per_second) {}
  /// True when a line may be logged now; then `*held_back` is how many were not since the last
  /// line let through (say so in the line).
  bool Allow(std::int64_t* held_back, Clock::time_point now = Clock::now());

 private:
  const int per_second_;
  std::mutex mutex_;
  Clock::time_point window_{};
  int lines_ = 0;
  std::int64_t held_back_ = 0;
};

}  // namespace saccade
