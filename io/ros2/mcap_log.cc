// The MCAP log over the reference MCAP library (third_party/mcap, MIT), zstd-compressed chunks.
#define MCAP_IMPLEMENTATION
#define MCAP_COMPRESSION_NO_LZ4
#include <mcap/writer.hpp>

#include "core/fail.h"
#include "io/base/log.h"
#include "io/lcm/lcm_decode.h"
#include "io/lcm/lcm_log.h"
#include "io/lcm/preview.h"
#include "io/ros2/mcap_log.h"
#include "io/ros2/ros2_messages.h"

#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>
#include <saccade/status_t.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <optional>

namespace saccade {

namespace {

// mcap's own FileWriter ignores a short write: this one remembers the first failure, so that a
// full disk is reported, never taken for a whole file.
class CheckedFile final : public mcap::IWritable {
 public:
  ~CheckedFile() override { end(); }
  bool Open(const std::string& path) {
    file_ = std::fopen(path.c_str(), "wb");
    if (!file_) failure_ = std::strerror(errno);
    return file_ != nullptr;
  }
  void handleWrite(const std::byte* data, uint64_t size) override {
    if (!file_ || !failure_.empty()) return;
    if (std::fwrite(data, 1, size, file_) != size) failure_ = std::strerror(errno);
    size_ += size;
  }
  void flush() override {
    if (file_ && failure_.empty() && std::fflush(file_) != 0) failure_ = std::strerror(errno);
  }
  void end() override {
    if (!file_) return;
    if (std::fflush(file_) != 0 && failure_.empty()) failure_ = std::strerror(errno);
    if (std::fclose(file_) != 0 && failure_.empty()) failure_ = std::strerror(errno);
    file_ = nullptr;
  }
  uint64_t size() const override { return size_; }
  const std::string& failure() const { return failure_; }

 private:
  std::FILE* file_ = nullptr;
  uint64_t size_ = 0;
  std::string failure_;
};

class McapFile : public McapLog {
 public:
  // `chunk_bytes`: how much is compressed at a time (and so how far behind the file's size is
  // what was given); 0 for the library's default.
  McapFile(const std::string& path, const Ros2Options& options, std::uint64_t chunk_bytes = 0)
      : path_(path),
        part_(path + ".part"),
        naming_{options.camera_frame_id, options.topic_prefix},
        chunk_bytes_(chunk_bytes) {}

  ~McapFile() override {
    if (open_) {
      writer_.terminate();
      file_.end();
      std::remove(part_.c_str());
    }
  }

  bool Open(std::string* error) {
    if (!file_.Open(part_))
      return Fail(error, part_ + ": cannot create the MCAP log: " + file_.failure());
    mcap::McapWriterOptions options("ros2");  // rosbag2's profile
    options.compression = mcap::Compression::Zstd;
    if (chunk_bytes_ > 0) options.chunkSize = chunk_bytes_;
    options.library = "saccade (mcap " MCAP_LIBRARY_VERSION ")";
    writer_.open(file_, options);
    open_ = true;
    detections_ = Channel(naming_.DetectionsTopic(), "vision_msgs/msg/Detection3DArray");
    fixation_ = Channel(naming_.FixationTopic(), "geometry_msgs/msg/PointStamped");
    diagnostics_ = Channel("/diagnostics", "diagnostic_msgs/msg/DiagnosticArray");
    return Check(error);
  }

  bool Detections(const detections_t& d, std::int64_t log_utime, std::string* error) override {
    const Ros2Detections m(d, naming_);
    Write(detections_, SerializeCdr(&m.message, vision_msgs_msg_dds__Detection3DArray__desc),
          log_utime, d.publish_utime);
    return Check(error);
  }

  bool Fixation(const fixation_t& f, std::int64_t log_utime, std::string* error) override {
    const Ros2Fixation m(f, naming_);
    Write(fixation_, SerializeCdr(&m.message, geometry_msgs_msg_dds__PointStamped__desc), log_utime,
          log_utime);
    return Check(error);
  }

  bool Status(const status_t& s, std::int64_t log_utime, std::string* error) override {
    if (!diagnostics_state_.Take(s)) return Check(error);
    ++diagnostics_written_;
    Write(diagnostics_,
          SerializeCdr(&diagnostics_state_.message, diagnostic_msgs_msg_dds__DiagnosticArray__desc),
          log_utime, s.utime);
    return Check(error);
  }

  std::int64_t DiagnosticsWritten() const { return diagnostics_written_; }

  bool Preview(const DecodedPreview& p, std::int64_t log_utime, std::string* error) override {
    if (cloud_ == 0) {  // the first preview: the log has them
      cloud_ = Channel(naming_.CloudTopic(), "sensor_msgs/msg/PointCloud2");
      image_ = Channel(naming_.ImageTopic(), "sensor_msgs/msg/CompressedImage");
    }
    const Ros2Preview m(p, naming_);
    Write(cloud_, SerializeCdr(&m.cloud, sensor_msgs_msg_dds__PointCloud2__desc), log_utime,
          p.utime);
    if (p.image_format == "jpeg")
      Write(image_, SerializeCdr(&m.image, sensor_msgs_msg_dds__CompressedImage__desc), log_utime,
            p.utime);
    return Check(error);
  }

  std::uint64_t Bytes() const override { return file_.size(); }
  std::int64_t Messages() const override { return messages_; }

  bool Close(std::string* error) override {
    if (!open_) return Fail(error, path_ + ": the MCAP log was already closed");
    writer_.close();
    file_.end();
    open_ = false;
    if (!file_.failure().empty()) {
      std::remove(part_.c_str());
      return Fail(error, part_ + ": writing the MCAP log failed: " + file_.failure() +
                             " (nothing left under " + path_ + ")");
    }
    if (std::rename(part_.c_str(), path_.c_str()) != 0) {
      const std::string why = std::strerror(errno);
      std::remove(part_.c_str());
      return Fail(error, path_ + ": cannot rename the MCAP log into place: " + why);
    }
    return true;
  }

 private:
  mcap::ChannelId Channel(const std::string& topic, const std::string& type) {
    mcap::Schema schema(type, "ros2msg", Ros2MessageDefinition(type));
    writer_.addSchema(schema);
    mcap::Channel channel(topic, "cdr", schema.id);
    writer_.addChannel(channel);
    return channel.id;
  }

  void Write(mcap::ChannelId channel, const std::vector<std::uint8_t>& bytes,
             std::int64_t log_utime, std::int64_t publish_utime) {
    mcap::Message m;
    m.channelId = channel;
    m.sequence = static_cast<std::uint32_t>(++sequence_[channel]);
    m.logTime = static_cast<mcap::Timestamp>(log_utime) * 1000;
    m.publishTime =
        static_cast<mcap::Timestamp>(publish_utime > 0 ? publish_utime : log_utime) * 1000;
    m.data = reinterpret_cast<const std::byte*>(bytes.data());
    m.dataSize = bytes.size();
    const mcap::Status status = writer_.write(m);
    if (!status.ok() && failure_.empty()) failure_ = status.message;
    ++messages_;
  }

  bool Check(std::string* error) const {
    if (!file_.failure().empty())
      return Fail(error, part_ + ": writing the MCAP log failed: " + file_.failure());
    if (!failure_.empty()) return Fail(error, part_ + ": " + failure_);
    return true;
  }

  const std::string path_, part_;
  const Ros2Naming naming_;
  const std::uint64_t chunk_bytes_;
  CheckedFile file_;
  mcap::McapWriter writer_;
  bool open_ = false;
  mcap::ChannelId detections_ = 0, fixation_ = 0, diagnostics_ = 0, cloud_ = 0, image_ = 0;
  std::map<mcap::ChannelId, std::uint64_t> sequence_;
  Ros2Diagnostics diagnostics_state_;
  std::int64_t messages_ = 0, diagnostics_written_ = 0;
  std::string failure_;
};

std::int64_t NowUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// saccaded's MCAP log: rotated by size, each file closed whole.
class McapMirror : public MessageMirror {
 public:
  McapMirror(const std::string& path, std::uint64_t max_bytes, const Ros2Options& options)
      : path_(path), max_bytes_(max_bytes), options_(options) {}

  ~McapMirror() override { CloseCurrent(); }

  bool Open(std::string* error) {
    // Chunks of at most an eighth of a file, so that the size checked follows what was logged.
    auto log = std::make_unique<McapFile>(NextPath(), options_,
                                          std::min<std::uint64_t>(max_bytes_ / 8, 768 * 1024));
    if (!log->Open(error)) return false;
    log_ = std::move(log);
    return true;
  }

  void Publish(const detections_t& d, const fixation_t& f) override {
    if (!log_) return;
    std::string error;
    const std::int64_t now = NowUtime();
    if (!log_->Detections(d, now, &error) || !log_->Fixation(f, now, &error)) return Failed(error);
    if (log_->Bytes() >= max_bytes_) {
      CloseCurrent();
      if (!Open(&error)) Failed(error);
    }
  }

  void PublishStatus(const status_t& s) override {
    std::string error;
    if (log_ && !log_->Status(s, NowUtime(), &error)) Failed(error);
  }

  void PublishPreview(const std::vector<std::uint8_t>& encoded) override {
    std::string why;
    const std::optional<DecodedPreview> p = DecodePreview(encoded.data(), encoded.size(), &why);
    std::string error;
    if (log_ && p && !log_->Preview(*p, NowUtime(), &error)) Failed(error);
  }

  std::string Describe() const override { return "MCAP log " + path_; }

 private:
  // PATH, then PATH with -1, -2, ... before its extension.
  std::string NextPath() {
    const int n = files_++;
    if (n == 0) return path_;
    const std::size_t slash = path_.rfind('/');
    const std::size_t dot = path_.rfind('.');
    const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
    const std::string stem = has_ext ? path_.substr(0, dot) : path_;
    return stem + "-" + std::to_string(n) + (has_ext ? path_.substr(dot) : "");
  }

  void CloseCurrent() {
    if (!log_) return;
    std::string error;
    if (!log_->Close(&error)) Log(LogLevel::kError, "log.mcap: " + error);
    log_.reset();
  }

  // A failed write ends the log (what was closed before stays); the daemon goes on.
  void Failed(const std::string& error) {
    Log(LogLevel::kError, "log.mcap: " + error + "; the MCAP log stops here");
    log_.reset();  // removes the .part
  }

  const std::string path_;
  const std::uint64_t max_bytes_;
  const Ros2Options options_;
  std::unique_ptr<McapFile> log_;
  int files_ = 0;
};

}  // namespace

std::unique_ptr<McapLog> McapLog::Open(const std::string& path, const Ros2Options& options,
                                       std::string* error) {
  auto log = std::make_unique<McapFile>(path, options);
  if (!log->Open(error)) return nullptr;
  return log;
}

bool ConvertLcmLogToMcap(const std::string& log, const std::string& channel_prefix,
                         const std::string& out, const Ros2Options& options, McapCounts* counts,
                         std::string* error) {
  if (!CheckLcmLog(log, error)) return false;
  auto mcap = std::make_unique<McapFile>(out, options);
  if (!mcap->Open(error)) return false;
  const std::string detections = DetectionsChannel(channel_prefix),
                    fixation = FixationChannel(channel_prefix),
                    status = StatusChannel(channel_prefix),
                    preview = PreviewChannel(channel_prefix);
  std::string failure;
  LcmLogStats stats;
  const bool read = ReadLcmLogEvents(
      log,
      [&](const std::string& c) {
        return c == detections || c == fixation || c == status || c == preview;
      },
      // Returns whether the message decoded (counted as written, else skipped).
      [&](const LcmLogEvent& e) {
        if (!failure.empty()) return true;  // a write failed: the rest is not converted
        if (e.channel == detections) {
          const std::optional<detections_t> m = DecodeDetectionsMessage(e.data, e.size);
          if (!m) return false;
          ++counts->detections;
          mcap->Detections(*m, e.utime, &failure);  // a failed write is kept in `failure`
          return true;
        }
        if (e.channel == fixation) {
          const std::optional<fixation_t> m = DecodeFixationMessage(e.data, e.size);
          if (!m) return false;
          ++counts->fixations;
          mcap->Fixation(*m, e.utime, &failure);  // a failed write is kept in `failure`
          return true;
        }
        if (e.channel == status) {
          const std::optional<status_t> m = DecodeStatusMessage(e.data, e.size);
          if (!m) return false;
          mcap->Status(*m, e.utime, &failure);  // a failed write is kept in `failure`
          return true;
        }
        std::string why;
        const std::optional<DecodedPreview> p = DecodePreview(e.data, e.size, &why);
        if (!p) return false;
        ++counts->previews;
        mcap->Preview(*p, e.utime, &failure);  // a failed write is kept in `failure`
        return true;
      },
      &stats, error);
  counts->skipped = stats.skipped;
  counts->diagnostics = mcap->DiagnosticsWritten();
  if (!read) return false;  // the McapFile removes its .part
  if (!failure.empty()) return Fail(error, failure);
  if (stats.written == 0)
    return Fail(error, log + ": no message on " + channel_prefix + "_* decodes as saccaded's (" +
                           std::to_string(stats.skipped) +
                           " skipped: a log of an older saccaded, whose types had another "
                           "fingerprint, or of another prefix; see --channel-prefix)");
  return mcap->Close(error);
}

std::unique_ptr<MessageMirror> OpenMcapMirror(const std::string& path, std::uint64_t max_bytes,
                                              const Ros2Options& options, std::string* error) {
  auto mirror = std::make_unique<McapMirror>(path, max_bytes, options);
  if (!mirror->Open(error)) return nullptr;
  return mirror;
}

}  // namespace saccade
