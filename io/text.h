// Small string helpers shared by io's file handling.
#pragma once

#include <string>

namespace saccade {

/// True when `s` ends with `suffix` ("frame.pcd", ".pcd").
inline bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace saccade
