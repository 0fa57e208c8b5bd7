#include "io/log.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace saccade {
namespace {

std::mutex log_mutex;
std::string log_program = "saccade";  // guarded by log_mutex
std::atomic<LogLevel> log_level{LogLevel::kInfo};

const char* LevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug:
      return "debug";
    case LogLevel::kInfo:
      return "info";
    case LogLevel::kWarning:
      return "warning";
    case LogLevel::kError:
      return "error";
  }
  return "?";
}

}  // namespace

bool ParseLogLevel(const std::string& name, LogLevel* level) {
  for (LogLevel l : {LogLevel::kDebug, LogLevel::kInfo, LogLevel::kWarning, LogLevel::kError}) {
    if (name == LevelName(l)) {
      *level = l;
      return true;
    }
  }
  return false;
}

void ConfigureLog(const std::string& program, LogLevel level) {
  std::lock_guard<std::mutex> lock(log_mutex);
  log_program = program;
  log_level = level;
}

bool LogEnabled(LogLevel level) { return level >= log_level.load(); }

void Log(LogLevel level, const std::string& message) {
  if (level < log_level.load()) return;
  std::lock_guard<std::mutex> lock(log_mutex);
  std::fprintf(stderr, "%s: %s: %s\n", log_program.c_str(), LevelName(level), message.c_str());
  std::fflush(stderr);
}

bool LogLimiter::Allow(std::int64_t* held_back, Clock::time_point now) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (now - window_ >= std::chrono::seconds(1)) {
    window_ = now;
    lines_ = 0;
  }
  if (lines_ >= per_second_) {
    ++held_back_;
    return false;
  }
  ++lines_;
  *held_back = held_back_;
  held_back_ = 0;
  return true;
}

}  // namespace saccade
