#include "io/lcm/lcm_log.h"

#include "core/fail.h"
#include "io/base/text.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <vector>

namespace saccade {

std::int32_t LcmInt32(const unsigned char* p) {
  return static_cast<std::int32_t>((std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) |
                                   (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]});
}

bool LcmFieldsFit(const unsigned char* data, std::size_t size, std::size_t* at,
                  std::initializer_list<int> layout) {
  for (int field : layout) {
    if (*at > size) return false;
    if (field != kLcmString) {
      if (size - *at < static_cast<std::size_t>(field)) return false;
      *at += static_cast<std::size_t>(field);
      continue;
    }
    if (size - *at < 4) return false;
    const std::int32_t length = LcmInt32(data + *at);
    *at += 4;
    if (length < 1 || static_cast<std::size_t>(length) > size - *at) return false;
    *at += static_cast<std::size_t>(length);
  }
  return *at <= size;
}

namespace {

std::uint32_t Uint32(const unsigned char* p) { return static_cast<std::uint32_t>(LcmInt32(p)); }

}  // namespace

bool TableFormatOf(const std::string& path, TableFormat* format, std::string* error) {
  if (EndsWith(path, ".csv")) {
    *format = TableFormat::kCsv;
  } else if (EndsWith(path, ".jsonl")) {
    *format = TableFormat::kJsonl;
  } else {
    return Fail(error, "'" + path + "': the output must end in .csv or .jsonl");
  }
  return true;
}

namespace {

// lcm-logger's event (LCM's eventlog.c): the sync word, the event number and the time (int64
// each), the channel's length and the data's length (int32 each), then the channel and the
// data; big-endian. LCM limits a channel to 63 bytes.
constexpr std::uint32_t kLogSync = 0xEDA1DA01;
constexpr std::size_t kEventHeader = 4 + 8 + 8 + 4 + 4;
constexpr std::uint32_t kMaxChannel = 63;

}  // namespace

bool CheckLcmLog(const std::string& path, std::string* error) {
  std::uint64_t size = 0;
  if (!StatRegularFile(path, "an lcm-logger log", &size, error)) return false;
  if (size == 0) return Fail(error, path + ": empty file, not an lcm-logger log");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Fail(error, path + ": cannot read (" + std::strerror(errno) + ")");
  unsigned char sync[4] = {};
  if (!in.read(reinterpret_cast<char*>(sync), 4) || Uint32(sync) != kLogSync)
    return Fail(error, path + ": not an lcm-logger log (it does not start with an event)");
  return true;
}

namespace {

// The offset of the next sync word's first byte after `from`, or `size` when there is none:
// read in chunks, not a byte at a time.
std::uint64_t NextSync(std::ifstream& in, std::uint64_t from, std::uint64_t size) {
  std::vector<unsigned char> chunk(1 << 16);
  for (std::uint64_t at = from; at + 4 <= size; at += chunk.size() - 3) {
    const std::uint64_t n = std::min<std::uint64_t>(chunk.size(), size - at);
    in.clear();
    in.seekg(static_cast<std::streamoff>(at));
    if (!in.read(reinterpret_cast<char*>(chunk.data()), static_cast<std::streamsize>(n)))
      return size;
    for (std::uint64_t i = 0; i + 4 <= n; ++i)
      if (chunk[i] == 0xED && Uint32(&chunk[i]) == kLogSync) return at + i;
    if (n < chunk.size()) break;
  }
  return size;
}

}  // namespace

bool ReadLcmLog(const std::string& log_path, const std::string& channel,
                const std::function<bool(const unsigned char* data, std::size_t size)>& message,
                LcmLogStats* stats, std::string* error) {
  return ReadLcmLogEvents(
      log_path, [&](const std::string& name) { return name == channel; },
      [&](const LcmLogEvent& e) { return message(e.data, e.size); }, stats, error);
}

bool ReadLcmLogEvents(const std::string& log_path,
                      const std::function<bool(const std::string& channel)>& wanted,
                      const std::function<bool(const LcmLogEvent& event)>& message,
                      LcmLogStats* stats, std::string* error) {
  if (!CheckLcmLog(log_path, error)) return false;
  std::ifstream in(log_path, std::ios::binary);
  in.seekg(0, std::ios::end);
  const std::streamoff end = in.tellg();
  if (end < 0) return Fail(error, log_path + ": cannot read (its size is unknown)");
  const auto size = static_cast<std::uint64_t>(end);
  std::uint64_t at = 0;
  std::vector<unsigned char> header(kEventHeader), body;
  while (at < size) {
    in.clear();
    in.seekg(static_cast<std::streamoff>(at));
    // Lengths in 64 bits: a 32-bit sum of a lying data length wraps.
    const std::uint64_t left = size - at;
    bool event = left >= kEventHeader &&
                 in.read(reinterpret_cast<char*>(header.data()), kEventHeader).good() &&
                 Uint32(&header[0]) == kLogSync;
    const std::uint64_t channel_len = event ? Uint32(&header[20]) : 0;
    const std::uint64_t data_len = event ? Uint32(&header[24]) : 0;
    event = event && channel_len >= 1 && channel_len <= kMaxChannel &&
            data_len <= std::uint64_t{INT32_MAX} &&  // LCM's field is an int32
            kEventHeader + channel_len + data_len <= left;
    if (!event) {
      // Corrupt, or the last event cut short when the logger was killed: counted once, and
      // reading goes on at the next sync word.
      ++stats->skipped;
      at = NextSync(in, at + 1, size);
      continue;
    }
    std::string name(channel_len, '\0');
    in.read(name.data(), static_cast<std::streamsize>(channel_len));
    at += kEventHeader + channel_len + data_len;
    if (!wanted(name)) continue;  // other channels' data is not read
    body.resize(static_cast<std::size_t>(data_len));
    if (!in.read(reinterpret_cast<char*>(body.data()), static_cast<std::streamsize>(data_len)))
      break;
    std::int64_t utime = 0;
    for (int i = 0; i < 8; ++i)
      utime = static_cast<std::int64_t>((static_cast<std::uint64_t>(utime) << 8) | header[12 + i]);
    if (message({name, utime, body.data(), body.size()}))
      ++stats->written;
    else
      ++stats->skipped;
  }
  return true;
}

}  // namespace saccade
