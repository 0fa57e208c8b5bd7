// Preconditions, checked: a violated one is a bug in the caller, and the program stops with
// what was expected and where (STYLE.md: bugs abort with a message; expected failures are
// values, see fail.h).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace saccade::internal {

[[noreturn]] inline void CheckFailed(const char* condition, const std::string& message,
                                     const char* file, int line) {
  std::fprintf(stderr, "%s:%d: precondition failed: %s%s%s\n", file, line, condition,
               message.empty() ? "" : ": ", message.c_str());
  std::abort();
}

}  // namespace saccade::internal

/// Aborts with `message` (a std::string or a literal) when `condition` is false.
#define SACCADE_CHECK(condition, message)                                                        \
  do {                                                                                           \
    if (!(condition)) ::saccade::internal::CheckFailed(#condition, message, __FILE__, __LINE__); \
  } while (0)

/// Aborts with the reason when `options.IsValid(&why)` is false.
#define SACCADE_CHECK_VALID(options)                                                       \
  do {                                                                                     \
    std::string saccade_check_why;                                                         \
    if (!(options).IsValid(&saccade_check_why))                                            \
      ::saccade::internal::CheckFailed(#options ".IsValid()", saccade_check_why, __FILE__, \
                                       __LINE__);                                          \
  } while (0)
