#include "io/base/log.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace saccade {
namespace {

std::mutex log_mutex;
std::string log_program = "saccade";  // guarded by log_mutex
std::atomic<LogLevel> log_level{LogLevel::kInfo};
bool log_to_journal = false;  // guarded by log_mutex

// syslog's priorities, which journald reads from a line's "<N>" prefix (sd-daemon(3)).
int JournalPriority(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug:
      return 7;
    case LogLevel::kInfo:
      return 6;
    case LogLevel::kWarning:
      return 4;
    case LogLevel::kError:
      return 3;
  }
  return 6;
}

// True when stderr is journald's stream: systemd sets $JOURNAL_STREAM to its "device:inode"
// (systemd.exec(5)); a redirected stderr (a file, a pipe to a shell) has another.
bool StderrIsTheJournal() {
  const char* stream = std::getenv("JOURNAL_STREAM");
  struct stat st {};
  if (stream == nullptr || fstat(STDERR_FILENO, &st) != 0) return false;
  unsigned long long device = 0, inode = 0;
  char end = 0;
  if (std::sscanf(stream, "%llu:%llu%c", &device, &inode, &end) != 2) return false;
  return device == static_cast<unsigned long long>(st.st_dev) &&
         inode == static_cast<unsigned long long>(st.st_ino);
}

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
  log_to_journal = StderrIsTheJournal();
}

bool LogEnabled(LogLevel level) { return level >= log_level.load(); }

void Log(LogLevel level, const std::string& message) {
  if (level < log_level.load()) return;
  std::lock_guard<std::mutex> lock(log_mutex);
  if (log_to_journal) std::fprintf(stderr, "<%d>", JournalPriority(level));
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
