// Leveled, line-at-a-time logging to stderr: "saccaded: warning: what (where)". Thread-safe.
#pragma once

#include <string>

namespace saccade {

enum class LogLevel { kDebug, kInfo, kWarning, kError };

/// Parses debug | info | warning | error.
bool ParseLogLevel(const std::string& name, LogLevel* level);
/// Process-wide settings: lines below `level` are dropped; `program` starts every line.
void ConfigureLog(const std::string& program, LogLevel level);
void Log(LogLevel level, const std::string& message);
/// True when lines of `level` are written (to skip building a message nobody will see).
bool LogEnabled(LogLevel level);

}  // namespace saccade
