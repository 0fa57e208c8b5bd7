// saccaded's messages as ROS 2 messages in an MCAP file (docs/ROS2.md, "MCAP logs"): profile
// ros2, messages in CDR, schemas in ros2msg holding each type's full definition as rosbag2
// writes them, so that Foxglove opens it and `ros2 bag play` plays it. Written through the
// reference MCAP library (third_party/mcap) with Debian's libzstd, beside its final name and
// renamed when closed whole.
#pragma once

#include "io/lcm/bus.h"
#include "io/ros2/ros2.h"

#include <cstdint>
#include <memory>
#include <string>

namespace saccade {

struct DecodedPreview;

class McapLog {
 public:
  /// Opens PATH.part for writing; nullptr with one line in `error` when it cannot be.
  static std::unique_ptr<McapLog> Open(const std::string& path, const Ros2Options& options,
                                       std::string* error);
  virtual ~McapLog() = default;
  /// A frame's PREFIX/detections and its PREFIX/fixation, logged at `log_utime` (epoch
  /// microseconds). False, with one line in `error`, once a write has failed.
  virtual bool Detections(const detections_t& d, std::int64_t log_utime, std::string* error) = 0;
  virtual bool Fixation(const fixation_t& f, std::int64_t log_utime, std::string* error) = 0;
  /// /diagnostics, once a second of statuses.
  virtual bool Status(const status_t& s, std::int64_t log_utime, std::string* error) = 0;
  /// A preview: its points on PREFIX/foveated_cloud (sensor_msgs/msg/PointCloud2) and its
  /// JPEG on PREFIX/preview/compressed (sensor_msgs/msg/CompressedImage).
  virtual bool Preview(const DecodedPreview& p, std::int64_t log_utime, std::string* error) = 0;
  /// Bytes written so far, and messages.
  virtual std::uint64_t Bytes() const = 0;
  virtual std::int64_t Messages() const = 0;
  /// Writes the summary and the footer and renames PATH.part to PATH. False, with one line in
  /// `error` and PATH.part removed, when anything failed to be written.
  virtual bool Close(std::string* error) = 0;
};

/// What a conversion wrote, by kind, and the messages on saccaded's channels that did not
/// decode (or corrupt stretches of the log).
struct McapCounts {
  std::int64_t detections = 0, fixations = 0, diagnostics = 0, previews = 0, skipped = 0;
};

/// `saccade mcap`: the detections, fixations, statuses and previews of an lcm-logger log of
/// saccaded (channels PREFIX_*) as an MCAP file at `out`, each message logged at the time the
/// logger received it. The log is checked before anything is written; a log in which nothing
/// decodes, or a failed write, leaves no file. False with one line in `error`.
bool ConvertLcmLogToMcap(const std::string& log, const std::string& channel_prefix,
                         const std::string& out, const Ros2Options& options, McapCounts* counts,
                         std::string* error);

/// For saccaded (`log.mcap: PATH`): every message LCM sends, logged at its sending, into PATH;
/// past `max_bytes` the file is closed whole and the next one opened as PATH with -1, -2, ...
/// before its extension. The last one is closed when the mirror is destroyed (SIGTERM).
std::unique_ptr<MessageMirror> OpenMcapMirror(const std::string& path, std::uint64_t max_bytes,
                                              const Ros2Options& options, std::string* error);

}  // namespace saccade
