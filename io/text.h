// Small string helpers shared by io's file handling.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

namespace saccade {

/// True when `s` ends with `suffix` ("frame.pcd", ".pcd").
inline bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// std::filesystem's questions without its exceptions: a path it cannot ask about (a name
/// longer than the system allows, a folder it may not search) is not there.
inline bool PathExists(const std::string& path) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}
inline bool IsDirectory(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_directory(path, ec);
}
inline bool IsRegularFile(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

}  // namespace saccade
