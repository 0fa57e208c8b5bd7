// What the file-reading fuzz targets share: the input written to a file of this process (the
// loaders take paths), and the one-line rule every refusal must keep.
#pragma once

#include <unistd.h>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace saccade::fuzz {

/// Writes `size` bytes to /tmp/saccade-fuzz-PID.EXT and returns the path.
/// The file is removed when the process ends.
inline std::string WriteInput(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  const std::string path = "/tmp/saccade-fuzz-" + std::to_string(getpid()) + "." + ext;
  static std::vector<std::string> written;  // each extension's file, removed at exit
  if (std::find(written.begin(), written.end(), path) == written.end()) {
    written.push_back(path);
    if (written.size() == 1)
      std::atexit([] {
        for (const auto& p : written) std::remove(p.c_str());
      });
  }
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) __builtin_trap();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) __builtin_trap();
  std::fclose(f);
  return path;
}

/// A refusal must say why in one line.
inline void CheckRefusal(bool ok, const std::string& error) {
  if (!ok && (error.empty() || error.find('\n') != std::string::npos)) __builtin_trap();
}

}  // namespace saccade::fuzz
