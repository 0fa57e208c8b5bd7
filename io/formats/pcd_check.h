// A PCD file checked whole before PCL parses it: PCL's reader trusts the header (a lying
// WIDTH, SIZE or compressed size overflows its buffers or allocates gigabytes) and crashes on
// files that are not PCD at all, so nothing reaches it that has not passed here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

/// What a PCD header says, as far as Saccade reads it.
struct PcdHeader {
  struct Field {
    std::string name;
    int size = 4;     // bytes per element: 1, 2, 4 or 8
    char type = 'F';  // I (signed), U (unsigned), F (float)
    int count = 1;    // elements
  };
  std::vector<Field> fields;
  std::uint64_t width = 0, height = 1, points = 0;
  enum class Data { kAscii, kBinary, kBinaryCompressed } data = Data::kAscii;
  std::uint64_t data_offset = 0;  // where the data starts in the file
  std::uint64_t point_bytes = 0;  // bytes of one point: sum of size x count

  int FieldIndex(const std::string& name) const;
};

/// Checks the PCD file at `path` (any data kind) and fills `header`: a regular file no larger
/// than 4 GB whose header has every keyword it needs, consistent counts, known types and sizes,
/// WIDTH x HEIGHT = POINTS (at most 100 million), float32 x, y and z, 4-byte rgb/rgba/label when
/// present, and data of the length the header implies: ASCII lines of numbers, binary bytes, or
/// binary_compressed sizes that agree with the file and decompress to exactly the points' bytes.
/// False with one line, "PATH: what is wrong", otherwise.
bool CheckPcdFile(const std::string& path, PcdHeader* header, std::string* error);

/// The same on bytes already in memory (`name` for messages): what a fuzzer drives.
bool CheckPcdBytes(const std::string& name, const std::string& bytes, PcdHeader* header,
                   std::string* error);

}  // namespace saccade
