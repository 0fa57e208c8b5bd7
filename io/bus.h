// The daemon's messages to the robot and its commands from it, over LCM (docs/LCM.md). The
// pipeline speaks these plain structs; only bus.cc knows the generated LCM types, so tests can
// use memq:// or a real multicast URL through the same interface.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace saccade {

/// One instance as published. Poses and points are in the camera frame here; the bus moves
/// them into the robot frame when BusOptions::robot_from_camera is set.
struct InstanceReport {
  int model = 0;
  std::string model_name;
  Eigen::Matrix4f camera_from_model = Eigen::Matrix4f::Identity();  // X_CM
  Eigen::Vector3f centroid_m = Eigen::Vector3f::Zero();
  int votes = 0;
  // Verification's figures (Detection's): -1 when not measured.
  float confidence = -1, fitness = -1, coverage = -1, colour_agreement = -1;
};

/// What one processed frame produced: SACCADE_DETECTIONS.
struct FrameReport {
  std::int64_t capture_utime = 0;
  std::int64_t seq = 0;
  bool foveated = true;
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();  // the fovea this frame was foveated at
  float growth_m = 0;
  std::int64_t fixation_seq = -1;  // the frame whose fixation was used
  float recognize_ms = 0;
  std::vector<InstanceReport> instances;
};

/// Where attention looks next: SACCADE_FIXATION (attention's Fixation, for the wire).
struct FixationReport {
  std::int64_t capture_utime = 0;
  std::int64_t seq = 0;
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();
  Eigen::Vector3f velocity_mps = Eigen::Vector3f::Zero();
  float growth_m = 0;
  int mode = 1;  // 0 TRACKING, 1 SEARCHING, 2 FULL_SCAN (fixation_t's constants and names)
  int target = -1;
  int model = -1;
  int num_targets = 0;
  std::string reason;
};

struct LatencyReport {
  std::string name;
  int samples = 0;
  float p50_ms = 0, p90_ms = 0, p99_ms = 0, max_ms = 0;
};

/// The 1 Hz heartbeat: SACCADE_STATUS.
struct StatusReport {
  double uptime_s = 0;
  std::string source;
  std::string source_state;
  bool paused = false;
  std::int64_t frames_in = 0, frames_processed = 0, frames_dropped = 0, source_reconnects = 0;
  float fps = 0;
  std::int64_t commands_accepted = 0, commands_rejected = 0;
  int fixation_lag_max = 0;
  int mode = 1;
  std::vector<LatencyReport> stages;
};

/// A request from SACCADE_COMMAND, already checked and moved into the camera frame.
struct Command {
  enum class Kind { kSetFovea = 1, kReset = 2, kSwitchModel = 3, kPause = 4, kResume = 5 };
  Kind kind = Kind::kReset;
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();  // kSetFovea, camera frame
  std::string model;                                  // kSwitchModel
};

struct BusOptions {
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string channel_prefix = "SACCADE";  // channels are PREFIX_DETECTIONS, PREFIX_FIXATION, ...
  bool commands = true;                    // subscribe to PREFIX_COMMAND
  /// Publish in the robot frame: X_RC, the camera C in the robot frame R, and R's name.
  bool to_robot_frame = false;
  Eigen::Isometry3f robot_from_camera = Eigen::Isometry3f::Identity();
  std::string robot_frame = "base_link";
  /// A SET_FOVEA farther than this from the camera is out of range, metres.
  float max_fovea_distance_m = 10.0f;
};

/// Called on the bus's receiving thread for each well-formed command; returns false with a
/// reason to reject it (a model that does not load, say).
using CommandHandler = std::function<bool(const Command& command, std::string* why)>;

/// Publishing is thread-safe.
class Bus {
 public:
  virtual ~Bus() = default;
  /// One DETECTIONS and one FIXATION message. False when LCM refused to send.
  virtual bool Publish(const FrameReport& frame, const FixationReport& fixation) = 0;
  virtual bool PublishStatus(const StatusReport& status) = 0;
  /// Commands accepted by the handler, and rejected so far: undecodable, unknown kind, out of
  /// range, or refused by the handler. Each rejection is also logged as a warning.
  virtual std::int64_t AcceptedCommands() const = 0;
  virtual std::int64_t RejectedCommands() const = 0;
  virtual std::string Describe() const = 0;
};

/// Opens LCM at options.url and, with commands on, a thread that receives them and passes
/// them to `on_command`. nullptr with one line in `error` when LCM cannot be opened.
std::unique_ptr<Bus> OpenLcmBus(const BusOptions& options, CommandHandler on_command,
                                std::string* error);

/// The channel names for a prefix.
std::string DetectionsChannel(const std::string& prefix);
std::string FixationChannel(const std::string& prefix);
std::string StatusChannel(const std::string& prefix);
std::string CommandChannel(const std::string& prefix);

}  // namespace saccade
