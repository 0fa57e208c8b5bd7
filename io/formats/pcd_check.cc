#include "io/formats/pcd_check.h"

#include "core/fail.h"
#include "io/base/text.h"

#include <pcl/io/lzf.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace saccade {

namespace {

constexpr std::uint64_t kMaxFileBytes = 4ull << 30;
constexpr std::uint64_t kMaxPoints = 100'000'000;
constexpr int kMaxCount = 100'000;  // elements of one field (a descriptor has hundreds)
constexpr std::size_t kMaxHeaderLines = 1000;

bool Fail(std::string* error, const std::string& name, const std::string& why) {
  return saccade::Fail(error, name + ": " + why);
}

// A whole number in [lo, hi] spelled as digits only.
bool ParseCount(const std::string& token, std::uint64_t lo, std::uint64_t hi, std::uint64_t* out) {
  if (token.empty() || token.size() > 19 ||
      !std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return false;
  *out = std::strtoull(token.c_str(), nullptr, 10);
  return *out >= lo && *out <= hi;
}

// A number as PCL writes it in ASCII data, "nan" and "inf" included.
bool IsNumber(const char* begin, const char* end) {
  if (begin == end) return false;
  const std::string token(begin, end);
  char* stop = nullptr;
  std::strtod(token.c_str(), &stop);
  return stop == token.c_str() + token.size();
}

bool CheckAscii(const std::string& name, const std::string& bytes, const PcdHeader& h,
                std::string* error) {
  std::uint64_t values = 0;
  for (const auto& f : h.fields) values += static_cast<std::uint64_t>(f.count);
  std::uint64_t line = 0;
  std::size_t at = h.data_offset;
  while (line < h.points && at < bytes.size()) {
    std::size_t end = bytes.find('\n', at);
    if (end == std::string::npos) end = bytes.size();
    const char* p = bytes.data() + at;
    const char* stop = bytes.data() + end;
    std::uint64_t n = 0;
    while (p < stop) {
      while (p < stop && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
      if (p == stop) break;
      const char* q = p;
      while (q < stop && *q != ' ' && *q != '\t' && *q != '\r') ++q;
      if (!IsNumber(p, q))
        return Fail(error, name,
                    "ASCII data line " + std::to_string(line + 1) + ": '" +
                        std::string(p, std::min<std::size_t>(q - p, 32)) + "' is not a number");
      ++n;
      p = q;
    }
    at = end + 1;
    if (n == 0) continue;  // a blank line
    if (n != values)
      return Fail(error, name,
                  "ASCII data line " + std::to_string(line + 1) + " has " + std::to_string(n) +
                      " values, the header says " + std::to_string(values));
    ++line;
  }
  if (line < h.points)
    return Fail(error, name,
                "ASCII data has " + std::to_string(line) + " points, the header says " +
                    std::to_string(h.points) + " (truncated?)");
  return true;
}

bool CheckBinary(const std::string& name, const std::string& bytes, const PcdHeader& h,
                 std::string* error) {
  const std::uint64_t need = h.points * h.point_bytes;
  const std::uint64_t have = bytes.size() - h.data_offset;
  if (h.data == PcdHeader::Data::kBinary) {
    if (have < need)
      return Fail(error, name,
                  "binary data is " + std::to_string(have) + " bytes, the header needs " +
                      std::to_string(need) + " (truncated?)");
    return true;
  }
  if (have < 8) return Fail(error, name, "binary_compressed data has no size words");
  std::uint32_t compressed = 0, uncompressed = 0;
  std::memcpy(&compressed, bytes.data() + h.data_offset, 4);
  std::memcpy(&uncompressed, bytes.data() + h.data_offset + 4, 4);
  if (compressed > have - 8)
    return Fail(error, name,
                "binary_compressed block says " + std::to_string(compressed) +
                    " bytes, the file has " + std::to_string(have - 8));
  if (uncompressed != need)
    return Fail(error, name,
                "binary_compressed block unpacks to " + std::to_string(uncompressed) +
                    " bytes, the header needs " + std::to_string(need));
  // LZF packs at most about 88 to 1 (a 3-byte back reference copies up to 264 bytes): a block
  // claiming more would have us allocate gigabytes for a small file.
  if (need > 100ull * compressed + 1024)
    return Fail(error, name,
                "binary_compressed block of " + std::to_string(compressed) +
                    " bytes cannot unpack to the " + std::to_string(need) + " the header needs");
  std::vector<char> out(need);
  const unsigned got = pcl::lzfDecompress(bytes.data() + h.data_offset + 8, compressed, out.data(),
                                          static_cast<unsigned>(need));
  if (got != need)
    return Fail(error, name,
                "binary_compressed block is corrupt (it does not unpack to " +
                    std::to_string(need) + " bytes)");
  return true;
}

}  // namespace

int PcdHeader::FieldIndex(const std::string& name) const {
  for (std::size_t i = 0; i < fields.size(); ++i)
    if (fields[i].name == name) return static_cast<int>(i);
  return -1;
}

bool CheckPcdBytes(const std::string& name, const std::string& bytes, PcdHeader* header,
                   std::string* error) {
  PcdHeader h;
  std::vector<std::string> names, sizes, types, counts;
  bool have_width = false, have_points = false, have_data = false;
  std::size_t at = 0;
  for (std::size_t lines = 0; !have_data; ++lines) {
    if (at >= bytes.size() || lines >= kMaxHeaderLines)
      return Fail(error, name,
                  lines == 0 ? "empty file, not a PCD file"
                             : "no DATA line: not a PCD file, or a truncated one");
    std::size_t end = bytes.find('\n', at);
    if (end == std::string::npos) end = bytes.size();
    std::string line = bytes.substr(at, std::min<std::size_t>(end - at, 1 << 16));
    at = end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (std::any_of(line.begin(), line.end(),
                    [](char c) { return static_cast<unsigned char>(c) < 0x20 && c != '\t'; }) ||
        std::any_of(line.begin(), line.end(),
                    [](char c) { return static_cast<unsigned char>(c) >= 0x80; }))
      return Fail(error, name, "not a PCD file (binary bytes in its header)");
    std::istringstream in(line);
    std::string key;
    if (!(in >> key) || key[0] == '#') continue;
    std::vector<std::string> values{std::istream_iterator<std::string>(in), {}};
    if (key == "VERSION") continue;
    if (key == "VIEWPOINT") {
      // The sensor's pose when the cloud was taken: normals are turned towards its origin, so it
      // must be seven finite numbers (tx ty tz qw qx qy qz) with a unit quaternion.
      double v[7];
      bool ok = values.size() == 7;
      for (std::size_t i = 0; ok && i < 7; ++i) {
        char* end_of = nullptr;
        v[i] = std::strtod(values[i].c_str(), &end_of);
        ok = *end_of == '\0' && std::isfinite(v[i]) && std::abs(v[i]) < 1e6;
      }
      const double norm = ok ? v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6] : 0;
      if (!ok || std::abs(norm - 1.0) > 1e-3)
        return Fail(error, name,
                    "VIEWPOINT must be tx ty tz qw qx qy qz: seven finite numbers, a unit "
                    "quaternion");
      continue;
    }
    if (key == "FIELDS" || key == "COLUMNS") {
      names = values;
    } else if (key == "SIZE") {
      sizes = values;
    } else if (key == "TYPE") {
      types = values;
    } else if (key == "COUNT") {
      counts = values;
    } else if (key == "WIDTH" || key == "HEIGHT" || key == "POINTS") {
      std::uint64_t v = 0;
      if (values.size() != 1 || !ParseCount(values[0], 1, kMaxPoints, &v))
        return Fail(error, name,
                    key + " must be a whole number from 1 to " + std::to_string(kMaxPoints));
      if (key == "WIDTH") h.width = v, have_width = true;
      if (key == "HEIGHT") h.height = v;
      if (key == "POINTS") h.points = v, have_points = true;
    } else if (key == "DATA") {
      if (values.size() != 1 ||
          (values[0] != "ascii" && values[0] != "binary" && values[0] != "binary_compressed"))
        return Fail(error, name, "DATA must be ascii, binary or binary_compressed");
      h.data = values[0] == "ascii"    ? PcdHeader::Data::kAscii
               : values[0] == "binary" ? PcdHeader::Data::kBinary
                                       : PcdHeader::Data::kBinaryCompressed;
      have_data = true;
      h.data_offset = std::min<std::uint64_t>(at, bytes.size());
    } else if (!names.empty() && IsNumber(key.data(), key.data() + key.size())) {
      return Fail(error, name, "no DATA line before the data");
    } else {
      return Fail(error, name,
                  lines == 0 && names.empty()
                      ? "not a PCD file (it starts with '" + key.substr(0, 16) + "')"
                      : "unknown header keyword '" + key.substr(0, 32) + "'");
    }
  }
  if (names.empty()) return Fail(error, name, "no FIELDS line");
  if (names.size() > 1000) return Fail(error, name, "more than 1000 fields");
  if (sizes.size() != names.size() || types.size() != names.size() ||
      (!counts.empty() && counts.size() != names.size()))
    return Fail(error, name, "FIELDS, SIZE, TYPE and COUNT list different numbers of entries");
  if (!have_width) return Fail(error, name, "no WIDTH line");
  if (h.width * h.height > kMaxPoints)
    return Fail(error, name,
                "WIDTH x HEIGHT is more than " + std::to_string(kMaxPoints) + " points");
  if (!have_points) h.points = h.width * h.height;
  if (h.points != h.width * h.height)
    return Fail(error, name,
                "POINTS " + std::to_string(h.points) + " is not WIDTH x HEIGHT " +
                    std::to_string(h.width * h.height));
  for (std::size_t i = 0; i < names.size(); ++i) {
    PcdHeader::Field f;
    f.name = names[i];
    std::uint64_t size = 0, count = 1;
    if (!ParseCount(sizes[i], 1, 8, &size) || (size != 1 && size != 2 && size != 4 && size != 8))
      return Fail(error, name, "field '" + f.name + "': SIZE must be 1, 2, 4 or 8");
    if (types[i] != "I" && types[i] != "U" && types[i] != "F")
      return Fail(error, name, "field '" + f.name + "': TYPE must be I, U or F");
    if (!counts.empty() && !ParseCount(counts[i], 1, kMaxCount, &count))
      return Fail(error, name,
                  "field '" + f.name + "': COUNT must be from 1 to " + std::to_string(kMaxCount));
    f.size = static_cast<int>(size);
    f.type = types[i][0];
    f.count = static_cast<int>(count);
    if (f.type == 'F' && f.size != 4 && f.size != 8)
      return Fail(error, name, "field '" + f.name + "': a float must be 4 or 8 bytes");
    h.point_bytes += size * count;
    h.fields.push_back(f);
  }
  for (const char* axis : {"x", "y", "z"}) {
    const int i = h.FieldIndex(axis);
    if (i < 0) return Fail(error, name, "PCD has no x, y and z fields");
    const auto& f = h.fields[static_cast<std::size_t>(i)];
    if (f.type != 'F' || f.size != 4 || f.count != 1)
      return Fail(error, name,
                  std::string("field '") + axis + "' is " + f.type + " " + std::to_string(f.size) +
                      " x" + std::to_string(f.count) +
                      "; Saccade reads x, y and z as single floats (TYPE F, SIZE 4, COUNT 1)");
  }
  for (const char* packed : {"rgb", "rgba", "label"}) {
    const int i = h.FieldIndex(packed);
    if (i < 0) continue;
    const auto& f = h.fields[static_cast<std::size_t>(i)];
    if (f.size != 4 || f.count != 1)
      return Fail(error, name, std::string("field '") + packed + "' must be 4 bytes, COUNT 1");
  }
  const bool ok = h.data == PcdHeader::Data::kAscii ? CheckAscii(name, bytes, h, error)
                                                    : CheckBinary(name, bytes, h, error);
  if (!ok) return false;
  *header = std::move(h);
  return true;
}

bool CheckPcdFile(const std::string& path, PcdHeader* header, std::string* error) {
  std::uint64_t size = 0;
  if (!StatRegularFile(path, "a PCD file", &size, error)) return false;
  if (size > kMaxFileBytes) return Fail(error, path, "larger than 4 GB");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Fail(error, path, "cannot open (permissions?)");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
    return Fail(error, path, "cannot read");
  return CheckPcdBytes(path, bytes, header, error);
}

}  // namespace saccade
