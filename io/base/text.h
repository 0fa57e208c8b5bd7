// Small string helpers shared by io's file handling.
#pragma once

#include "core/fail.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace saccade {

/// True when `s` ends with `suffix` ("frame.pcd", ".pcd").
/// `text` as one CSV field: quoted (with its quotes doubled) when it holds a comma, a quote or
/// a line break.
inline std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

/// A float as its shortest text that reads back as the same float ("0.2", not 0.200000003):
/// the precision it has, and no more.
inline std::string ShortestFloat(float value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::string(text, end);
}

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

/// Asks what `path` is without opening it (a FIFO or a device would block or never end): true
/// with its size (when `size` is given) for a regular file (links followed), else one line
/// naming the path and what it is instead of `kind` ("a PCD file").
inline bool StatRegularFile(const std::string& path, const std::string& kind, std::uint64_t* size,
                            std::string* error) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0)
    return Fail(error, path + ": " + (errno == ENOENT ? "no such file" : std::strerror(errno)));
  if (S_ISDIR(st.st_mode)) return Fail(error, path + ": is a directory, not " + kind);
  if (!S_ISREG(st.st_mode))
    return Fail(error, path + ": not a regular file (a device or a pipe?), not " + kind);
  if (size) *size = static_cast<std::uint64_t>(st.st_size);
  return true;
}

/// The regular files of `dir` (links followed), sorted by path; none when it cannot be listed.
/// Nothing throws: a link loop or an entry that cannot be asked about is skipped.
inline std::vector<std::string> RegularFilesIn(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type;
    if (it->is_regular_file(type)) out.push_back(it->path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace saccade
