// ROS 2's messages made from saccaded's LCM messages (docs/ROS2.md), as the C structs idlc
// generates from idl/: what the DDS mirror writes and the MCAP log stores. Internal to io/ros2
// (it includes Cyclone DDS and the generated types).
#pragma once

#include "io/lcm/bus.h"
#include "io/ros2/ros2.h"

#include <dds/dds.h>

#include "diagnostic_msgs.h"
#include "geometry_msgs.h"
#include "sensor_msgs.h"
#include "tf2_msgs.h"
#include "vision_msgs.h"

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace saccade {

/// How ROS 2 names what LCM calls "camera" (ros2.camera_frame_id), and the ROS 2 topics.
struct Ros2Naming {
  std::string camera_frame_id = "camera";
  std::string topic_prefix = "/saccade";
  std::string DetectionsTopic() const { return topic_prefix + "/detections"; }
  std::string FixationTopic() const { return topic_prefix + "/fixation"; }
  std::string CloudTopic() const { return topic_prefix + "/foveated_cloud"; }
  std::string ImageTopic() const { return topic_prefix + "/preview/compressed"; }
  /// LCM's frame name as ROS 2's header.frame_id.
  std::string FrameId(const std::string& lcm_frame) const {
    return lcm_frame == "camera" ? camera_frame_id : lcm_frame;
  }
};

/// A frame's PREFIX/detections. It points into strings and arrays held here: use it while
/// this lives.
class Ros2Detections {
 public:
  Ros2Detections(const detections_t& d, const Ros2Naming& naming);
  Ros2Detections(const Ros2Detections&) = delete;
  Ros2Detections& operator=(const Ros2Detections&) = delete;
  vision_msgs_msg_dds__Detection3DArray_ message{};

 private:
  std::deque<std::string> strings_;  // a deque: what was added does not move
  std::vector<vision_msgs_msg_dds__ObjectHypothesisWithPose_> results_;
  std::vector<vision_msgs_msg_dds__Detection3D_> detections_;
};

/// A frame's PREFIX/fixation, likewise.
class Ros2Fixation {
 public:
  Ros2Fixation(const fixation_t& f, const Ros2Naming& naming);
  Ros2Fixation(const Ros2Fixation&) = delete;
  Ros2Fixation& operator=(const Ros2Fixation&) = delete;
  geometry_msgs_msg_dds__PointStamped_ message{};

 private:
  std::string frame_id_;
};

struct DecodedPreview;

/// A preview's PREFIX/foveated_cloud (sensor_msgs/PointCloud2: x, y, z float32 metres and a
/// uint8 `tag`, preview_t's: the fovea's level, or 128 + the instance whose model point it is)
/// and PREFIX/preview/compressed (sensor_msgs/CompressedImage, its JPEG), both in the camera
/// frame. Likewise valid while this lives.
class Ros2Preview {
 public:
  Ros2Preview(const DecodedPreview& p, const Ros2Naming& naming);
  Ros2Preview(const Ros2Preview&) = delete;
  Ros2Preview& operator=(const Ros2Preview&) = delete;
  sensor_msgs_msg_dds__PointCloud2_ cloud{};
  sensor_msgs_msg_dds__CompressedImage_ image{};

 private:
  std::string frame_id_, format_;
  std::vector<sensor_msgs_msg_dds__PointField_> fields_;
  std::vector<std::uint8_t> points_, jpeg_;
};

/// /diagnostics from saccaded's statuses: one DiagnosticArray a second.
class Ros2Diagnostics {
 public:
  /// Whether `s` is due one (a second or more after the last); then `message` holds it, valid
  /// until the next call.
  bool Take(const status_t& s);
  diagnostic_msgs_msg_dds__DiagnosticArray_ message{};

 private:
  std::int64_t last_utime_ = 0, last_dropped_ = 0, last_unsent_ = 0;
  std::deque<std::string> strings_;
  std::vector<diagnostic_msgs_msg_dds__KeyValue_> values_;
  diagnostic_msgs_msg_dds__DiagnosticStatus_ status_{};
};

/// /tf_static: the camera (child, ros2.camera_frame_id) in the robot frame, stamped `utime`.
class Ros2TfStatic {
 public:
  Ros2TfStatic(const RobotFrameOptions& robot, const Ros2Naming& naming, std::int64_t utime);
  Ros2TfStatic(const Ros2TfStatic&) = delete;
  Ros2TfStatic& operator=(const Ros2TfStatic&) = delete;
  tf2_msgs_msg_dds__TFMessage_ message{};

 private:
  std::string parent_, child_;
  geometry_msgs_msg_dds__TransformStamped_ transform_{};
};

/// A message as ROS 2 sends and rosbag2 stores it: the CDR encapsulation header of
/// little-endian plain CDR (00 01 00 00), then the sample in XCDR1 as Cyclone DDS writes it.
std::vector<std::uint8_t> SerializeCdr(const void* sample, const dds_topic_descriptor_t& type);

/// A type's definition as rosbag2 stores it in an MCAP schema (encoding ros2msg): its .msg
/// fields, then each type it uses after a line of 80 '=' and "MSG: package/Type". `type` as
/// ROS 2 names it: "vision_msgs/msg/Detection3DArray".
std::string Ros2MessageDefinition(const std::string& type);

}  // namespace saccade
