// saccaded's messages on ROS 2's wire (docs/ROS2.md): DDS topics named and typed as a ROS 2
// node's (`rt/saccade/detections` of `vision_msgs::msg::dds_::Detection3DArray_`, ...), written
// through Eclipse Cyclone DDS, one of ROS 2's middlewares, with no ROS installed. Each message
// mirrors the LCM message LcmBus sends for the same frame (io/lcm/bus.h, MessageMirror). Commands
// stay on LCM, signed (docs/LCM.md). This header needs no DDS: a build without Cyclone DDS
// has Ros2Built() false and OpenRos2Mirror fails saying so.
#pragma once

#include "core/schema.h"
#include "io/lcm/bus.h"

#include <memory>
#include <string>

namespace saccade {

/// The `ros2` section of the config.
struct Ros2Options {
  bool enabled = false;                   // also `saccaded --ros2`
  std::string topic_prefix = "/saccade";  // PREFIX/detections, PREFIX/fixation
  /// header.frame_id of what is published in the camera frame (LCM names it "camera"); with a
  /// robot frame configured, the robot frame's name, and /tf_static links the two.
  std::string camera_frame_id = "camera";
  /// ROS 2's default QoS: reliable, volatile, keep last `depth`; false: best effort (as a
  /// sensor's topics).
  bool reliable = true;
  int depth = 10;
  bool diagnostics = true;  // /diagnostics, diagnostic_msgs/DiagnosticArray, once a second

  bool IsValid(std::string* error) const;
  bool operator==(const Ros2Options& o) const { return SameFields(*this, o); }
  bool operator!=(const Ros2Options& o) const { return !(*this == o); }
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("enabled", &enabled);
    a->Visit("topic_prefix", &topic_prefix);
    a->Visit("camera_frame_id", &camera_frame_id);
    a->Visit("reliable", &reliable);
    a->Visit("depth", &depth);
    a->Visit("diagnostics", &diagnostics);
  }
};

/// The `log` section: saccaded's own MCAP log of what it publishes (docs/ROS2.md).
struct McapLogOptions {
  std::string mcap;           // the file; empty: none
  double mcap_max_mb = 1024;  // a file is closed past this and the next one begun, MB

  bool IsValid(std::string* error) const;
  bool operator==(const McapLogOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const McapLogOptions& o) const { return !(*this == o); }
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("mcap", &mcap);
    a->Visit("mcap_max_mb", &mcap_max_mb);
  }
};

/// Whether this build speaks ROS 2 (Cyclone DDS was found at configure time).
bool Ros2Built();

/// A participant on the DDS domain ROS_DOMAIN_ID (0 when unset; CYCLONEDDS_URI configures
/// Cyclone as it would under a ROS 2 node) with the writers of docs/ROS2.md; /tf_static is
/// written once here when `robot.enabled`. nullptr with one line in `error` when DDS cannot be
/// joined, ROS_DOMAIN_ID is not 0-232, or the build has no DDS.
std::unique_ptr<MessageMirror> OpenRos2Mirror(const Ros2Options& options,
                                              const RobotFrameOptions& robot, std::string* error);

}  // namespace saccade
