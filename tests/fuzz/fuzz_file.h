// What the file-reading fuzz targets share: the input written to a file of this process (the
// loaders take paths), and the one-line rule every refusal must keep.
#pragma once

#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace saccade::fuzz {

/// Writes `size` bytes to /tmp/saccade-fuzz-PID.EXT and returns the path.
inline std::string WriteInput(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  const std::string path = "/tmp/saccade-fuzz-" + std::to_string(getpid()) + "." + ext;
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
