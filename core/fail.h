// The one way Saccade's functions report an expected failure: a message in an optional
// out-parameter and `false` returned, so callers can write `return Fail(error, "...");`.
#pragma once

#include <string>

namespace saccade {

/// Sets *error (when error is not null) to `message` and returns false.
inline bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

}  // namespace saccade
