// The daemon's messages to the robot and its commands from it, over LCM (docs/LCM.md). The
// pipeline speaks core's values (FrameDetections, Fixation) and the plain structs below; only
// bus.cc knows the generated LCM types and converts, once, on the way out and in. Tests drive
// the tracker with an in-memory bus (io/lcm/memory_bus.h) or LCM at memq:// or a multicast URL.
#pragma once

#include "core/fixation.h"
#include "core/pictures/preview.h"
#include "core/schema.h"
#include "core/types.h"
#include "io/lcm/command_key.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

class detections_t;  // the LCM types (io/lcm/lcmtypes), generated at build time
class fixation_t;
class status_t;

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
  std::int64_t frames_skipped = 0;  // frames the source could not read (a corrupt file)
  std::int64_t frames_unsent = 0;   // processed, but LCM refused their detections or fixation
  float fps = 0;
  std::int64_t commands_accepted = 0, commands_rejected = 0;
  /// Datagrams the kernel dropped from the LCM socket: commands that never arrived among them.
  std::int64_t lcm_datagrams_dropped = 0;
  int fixation_lag_max = 0;
  AttentionMode mode = AttentionMode::kSearching;
  std::vector<LatencyReport> stages;
};

/// A request from SACCADE_COMMAND, already checked and moved into the camera frame.
struct Command {
  enum class Kind { kSetFovea = 1, kReset = 2, kSwitchModel = 3, kPause = 4, kResume = 5 };
  Kind kind = Kind::kReset;
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();  // kSetFovea, camera frame
  std::string model;                                  // kSwitchModel
};

/// Where the camera C sits in the robot frame R, when poses are published in R.
struct RobotFrameOptions {
  bool enabled = false;  // publish in R (else in the camera frame, named "camera")
  std::string name = "base_link";
  Eigen::Vector3f translation_m = Eigen::Vector3f::Zero();       // C's origin in R
  Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();  // R_RC, [w, x, y, z]

  /// X_RC. Precondition: IsValid().
  Eigen::Isometry3f RobotFromCamera() const {
    Eigen::Isometry3f X_RC = Eigen::Isometry3f::Identity();
    X_RC.translate(translation_m);
    X_RC.rotate(rotation.normalized());
    return X_RC;
  }
  bool IsValid(std::string* error) const;
  bool operator==(const RobotFrameOptions& o) const { return SameFields(*this, o); }
  /// The keys of the `robot_frame` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("enabled", &enabled);
    a->Visit("name", &name);
    a->Visit("translation_m", &translation_m);
    a->Visit("rotation", &rotation);
  }
};

struct BusOptions {
  /// Who may command saccaded on PREFIX_COMMAND. kSigned: only commands signed with the key
  /// (io/lcm/command_key.h); kOpen: anyone who can reach the LCM group, so only with ttl=0;
  /// kAuto: signed when the key file exists, else open with ttl=0, else off.
  enum class Commands { kAuto, kOff, kSigned, kOpen };
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string channel_prefix = "SACCADE";  // channels are PREFIX_DETECTIONS, PREFIX_FIXATION, ...
  Commands commands = Commands::kAuto;
  std::string command_key = kDefaultCommandKeyPath;
  /// A signed command stamped further than this from the daemon's clock is refused, seconds.
  double command_max_age_s = 30.0;
  /// A SET_FOVEA farther than this from the camera is out of range, metres.
  float max_fovea_distance_m = 10.0f;
  /// SWITCH_MODEL loads only regular files under these folders (or synthetic:target); empty:
  /// the folders of the configured models.
  std::vector<std::string> model_dirs;
  RobotFrameOptions robot;

  /// The mode `kAuto` comes to on this machine (whether the key file exists); else `commands`.
  Commands Resolved() const;
  bool IsValid(std::string* error) const;
  bool operator==(const BusOptions& o) const { return SameFields(*this, o) && robot == o.robot; }
  bool operator!=(const BusOptions& o) const { return !(*this == o); }
  /// The keys of the `lcm` section (core/schema.h); `robot` is a section of its own.
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("url", &url);
    a->Visit("channel_prefix", &channel_prefix);
    // true and false: the older spelling (subscribe or not).
    a->Choice("commands", &commands,
              {{"auto", Commands::kAuto},
               {"off", Commands::kOff},
               {"signed", Commands::kSigned},
               {"open", Commands::kOpen},
               {"true", Commands::kAuto},
               {"false", Commands::kOff}});
    a->Visit("command_key", &command_key);
    a->Visit("command_max_age_s", &command_max_age_s);
    a->Visit("max_fovea_distance_m", &max_fovea_distance_m);
    a->Visit("model_dirs", &model_dirs);
  }
};

/// A saccade.command_t message's bytes as a Command, checked whole: its layout (the model
/// string's length before anything is allocated, at most 4096 bytes), its kind and its values
/// (a finite fovea within options.max_fovea_distance_m of the camera, after taking it from the
/// published frame through `robot_from_camera`). nullopt with why not, in one line.
std::optional<Command> DecodeCommand(const void* data, std::size_t size, const BusOptions& options,
                                     const Eigen::Isometry3f& robot_from_camera, std::string* why);

/// Whether a SWITCH_MODEL may load `spec`: synthetic:target, or a regular file (no pipe, device
/// or /proc entry) whose real path (links and ".." resolved) lies under one of `dirs`. False
/// with one line saying why not.
bool CommandModelAllowed(const std::string& spec, const std::vector<std::string>& dirs,
                         std::string* why);

/// The handler's verdict on a command, called once, from any thread, when it is known: a
/// command may be accepted at once (SET_FOVEA) or after work done elsewhere (SWITCH_MODEL is
/// accepted when the model is described, rejected with the reason when it cannot be).
using CommandReply = std::function<void(bool accepted, const std::string& why)>;
/// Called on the bus's receiving thread for each well-formed command; must return promptly
/// (slow work goes to another thread, which replies when done).
using CommandHandler = std::function<void(const Command& command, CommandReply reply)>;

/// Publishing is thread-safe.
class Bus {
 public:
  virtual ~Bus() = default;
  /// One DETECTIONS and one FIXATION message for a processed frame (the fixation's stamp is the
  /// frame's capture time). False when the transport refused to send.
  virtual bool Publish(const FrameDetections& frame, const Fixation& fixation) = 0;
  virtual bool PublishStatus(const StatusReport& status) = 0;
  /// A frame's preview (PREFIX_PREVIEW, core/pictures/preview.h), stamped with the frame's arrival.
  /// False, with one line in `error`, when it was not sent (it did not fit options.max_bytes,
  /// or the transport refused).
  virtual bool PublishPreview(const Preview& preview, std::int64_t arrival_steady_ns,
                              const PreviewOptions& options, std::string* error) = 0;
  /// Passes each well-formed command from now on to `handler` (nothing, with commands off in
  /// BusOptions). Called once, before the first command is wanted.
  virtual void Subscribe(CommandHandler handler) = 0;
  /// Commands accepted by the handler, and rejected so far: undecodable, unknown kind, out of
  /// range, or refused by the handler. Each rejection is also logged as a warning.
  virtual std::int64_t AcceptedCommands() const = 0;
  virtual std::int64_t RejectedCommands() const = 0;
  /// Datagrams the kernel dropped before the bus could read them (a full receive buffer: a
  /// message larger than it, or a flood), since the bus opened; 0 where nothing is dropped.
  virtual std::int64_t DroppedDatagrams() const { return 0; }
  virtual std::string Describe() const = 0;
};

/// Another transport handed every message the LCM bus sends, as it sends it (ROS 2:
/// io/ros2/ros2.h), so that both say the same of each frame. Called under the bus's publish
/// lock; must not block for long.
class MessageMirror {
 public:
  virtual ~MessageMirror() = default;
  /// A frame's messages.
  virtual void Publish(const detections_t& detections, const fixation_t& fixation) = 0;
  virtual void PublishStatus(const status_t& status) = 0;
  /// A preview_t's bytes as sent (io/lcm/preview.h decodes them).
  virtual void PublishPreview(const std::vector<std::uint8_t>& /*encoded*/) {}
  virtual std::string Describe() const = 0;
};

/// Opens LCM at options.url; with commands on, Subscribe starts a thread that receives them.
/// Every message sent is also handed to each of `mirrors`. nullptr with one line in `error`
/// when LCM cannot be opened.
std::unique_ptr<Bus> OpenLcmBus(const BusOptions& options, std::string* error,
                                std::vector<std::unique_ptr<MessageMirror>> mirrors = {});

/// The channel names for a prefix.
std::string DetectionsChannel(const std::string& prefix);
std::string FixationChannel(const std::string& prefix);
std::string StatusChannel(const std::string& prefix);
std::string CommandChannel(const std::string& prefix);
std::string PreviewChannel(const std::string& prefix);

}  // namespace saccade
