#include "io/fixation_log.h"

#include "core/fail.h"
#include "io/json.h"
#include "io/text.h"

#include <lcm/lcm-cpp.hpp>
#include <saccade/fixation_t.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <vector>

namespace saccade {

namespace {

// fixation_t as lcm-gen encodes it, after its 8-byte type hash: each field's size in bytes,
// kString for a string (a big-endian int32 length counting its final NUL, then the bytes).
constexpr int kString = -1;
constexpr int kFixationLayout[] = {8, 8, kString, 24, 24, 8, 1, kString, 4, 4, 4, kString};

std::uint32_t BigEndian32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

// True when the message holds every field and every string's length is at least 1 and within
// the message: lcm-gen's decoder checks only that a length is not past the end, so a length of
// 0 or below would make it copy (size_t)-1 bytes.
bool FixationFits(const unsigned char* data, std::size_t size) {
  std::size_t at = 8;
  for (int field : kFixationLayout) {
    if (field != kString) {
      at += static_cast<std::size_t>(field);
      if (at > size) return false;
      continue;
    }
    if (size - at < 4 || at > size) return false;
    const auto length = static_cast<std::int32_t>(BigEndian32(data + at));
    at += 4;
    if (length < 1 || static_cast<std::size_t>(length) > size - at) return false;
    at += static_cast<std::size_t>(length);
  }
  return at <= size;
}

}  // namespace

bool DecodeFixation(const void* data, std::size_t size, LoggedFixation* logged) {
  if (!FixationFits(static_cast<const unsigned char*>(data), size)) return false;
  saccade::fixation_t m;
  if (m.decode(data, 0, static_cast<int>(size)) < 0) return false;
  if (m.mode < 0 || m.mode > static_cast<int>(AttentionMode::kFullScan)) return false;
  logged->utime = m.utime;
  logged->frame = m.frame;
  Fixation& f = logged->fixation;
  f.frame_seq = m.seq;
  f.time_s = m.utime * 1e-6;
  for (int i = 0; i < 3; ++i) {
    f.fovea_m[i] = static_cast<float>(m.fovea[i]);
    f.velocity_mps[i] = static_cast<float>(m.velocity[i]);
  }
  f.growth_m = static_cast<float>(m.growth);
  f.mode = static_cast<AttentionMode>(m.mode);
  f.target = m.target;
  f.model = m.model;
  f.num_targets = m.num_targets;
  f.reason = m.reason;
  return true;
}

bool FixationWriter::FormatOf(const std::string& path, Format* format, std::string* error) {
  if (EndsWith(path, ".csv")) {
    *format = Format::kCsv;
  } else if (EndsWith(path, ".jsonl")) {
    *format = Format::kJsonl;
  } else {
    return Fail(error, "'" + path + "': the output must end in .csv or .jsonl");
  }
  return true;
}

FixationWriter::FixationWriter(std::ostream& out, Format format) : out_(out), format_(format) {
  if (format_ == Format::kCsv)
    out_ << "utime,seq,frame,fovea_x,fovea_y,fovea_z,velocity_x,velocity_y,velocity_z,growth,"
            "mode,target,model,num_targets,reason\n";
}

void FixationWriter::Write(const LoggedFixation& logged) {
  const Fixation& r = logged.fixation;
  if (format_ == Format::kCsv) {
    out_ << logged.utime << ',' << r.frame_seq << ',' << logged.frame << std::setprecision(9);
    for (float v : r.fovea_m) out_ << ',' << double{v};
    for (float v : r.velocity_mps) out_ << ',' << double{v};
    out_ << ',' << double{r.growth_m} << ',' << ModeName(r.mode) << ',' << r.target << ','
         << r.model << ',' << r.num_targets << ',' << r.reason << '\n';
  } else {
    JsonWriter j;
    j.BeginObject().Key("utime").Value(static_cast<long long>(logged.utime));
    j.Key("seq").Value(static_cast<long long>(r.frame_seq)).Key("frame").Value(logged.frame);
    j.Key("fovea").BeginArray();
    for (float v : r.fovea_m) j.Value(double{v});
    j.EndArray().Key("velocity").BeginArray();
    for (float v : r.velocity_mps) j.Value(double{v});
    j.EndArray()
        .Key("growth")
        .Value(double{r.growth_m})
        .Key("mode")
        .Value(std::string(ModeName(r.mode)));
    j.Key("target").Value(r.target).Key("model").Value(r.model);
    j.Key("num_targets").Value(r.num_targets).Key("reason").Value(r.reason).EndObject();
    out_ << j.str() << '\n';
  }
  out_.flush();
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
  if (!in.read(reinterpret_cast<char*>(sync), 4) || BigEndian32(sync) != kLogSync)
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
      if (chunk[i] == 0xED && BigEndian32(&chunk[i]) == kLogSync) return at + i;
    if (n < chunk.size()) break;
  }
  return size;
}

}  // namespace

bool ConvertFixationLog(const std::string& log_path, const std::string& channel,
                        FixationWriter* writer, FixationLogStats* stats, std::string* error) {
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
                 BigEndian32(&header[0]) == kLogSync;
    const std::uint64_t channel_len = event ? BigEndian32(&header[20]) : 0;
    const std::uint64_t data_len = event ? BigEndian32(&header[24]) : 0;
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
    if (name != channel) continue;  // other channels' data is not read
    body.resize(static_cast<std::size_t>(data_len));
    if (!in.read(reinterpret_cast<char*>(body.data()), static_cast<std::streamsize>(data_len)))
      break;
    LoggedFixation r;
    if (DecodeFixation(body.data(), body.size(), &r)) {
      writer->Write(r);
      ++stats->written;
    } else {
      ++stats->skipped;
    }
  }
  return true;
}

namespace {

struct Listener {
  FixationWriter* writer;
  FixationLogStats* stats;
  void On(const lcm::ReceiveBuffer* rbuf, const std::string&) {
    LoggedFixation r;
    if (DecodeFixation(rbuf->data, rbuf->data_size, &r)) {
      writer->Write(r);
      ++stats->written;
    } else {
      ++stats->skipped;
    }
  }
};

}  // namespace

bool ListenFixations(const std::string& url, const std::string& channel, FixationWriter* writer,
                     std::int64_t max_records, const std::atomic<bool>& stop,
                     FixationLogStats* stats, std::string* error) {
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    return Fail(error, "cannot open LCM at '" + url + "'");
  }
  Listener listener{writer, stats};
  lcm.subscribe(channel, &Listener::On, &listener);
  while (!stop && (max_records <= 0 || stats->written < max_records)) lcm.handleTimeout(200);
  return true;
}

}  // namespace saccade
