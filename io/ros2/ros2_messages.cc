#include "io/ros2/ros2_messages.h"

#include "io/lcm/preview.h"

#include <dds/ddsi/ddsi_cdrstream.h>
#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>
#include <saccade/status_t.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <utility>

namespace saccade {

namespace {

builtin_interfaces_msg_dds__Time_ Stamp(std::int64_t utime) {
  builtin_interfaces_msg_dds__Time_ t{};
  const std::int64_t sec = utime >= 0 ? utime / 1000000 : -((-utime + 999999) / 1000000);
  t.sec = static_cast<std::int32_t>(sec);
  t.nanosec = static_cast<std::uint32_t>((utime - sec * 1000000) * 1000);
  return t;
}

// ROS 2 strings are char*; the messages borrow them from a deque that does not move them.
char* Keep(std::deque<std::string>* strings, std::string s) {
  strings->push_back(std::move(s));
  return strings->back().data();
}

// A model's name as ROS 2 users label it: its file name without folder or extension
// ("/var/lib/saccade/models/mug.pcd" -> "mug", "synthetic:target" -> "target").
std::string ClassId(const std::string& spec) {
  const std::size_t cut = spec.find_last_of("/:");
  std::string name = spec.substr(cut == std::string::npos ? 0 : cut + 1);
  const std::size_t dot = name.rfind('.');
  if (dot != std::string::npos && dot > 0) name.erase(dot);
  return name;
}

// A detection's pose covariance (row-major, x y z then rotations about x y z): diagonal, a
// standard deviation of 1 cm and 1.5 degrees on each axis at confidence 1 (their 3D p90, 2.5 cm
// and 3.8 degrees, is about the 2.7 cm and 2.8 degrees a held track measures at p90 on the ViSP
// cube's real frames, docs/BENCHMARKS.md), growing as 1/confidence down to 0.05; all zeros
// (ROS's "unknown") when the instance was not verified.
void Covariance(float confidence, double out[36]) {
  std::fill(out, out + 36, 0.0);
  if (!(confidence >= 0)) return;
  const double c = std::clamp(static_cast<double>(confidence), 0.05, 1.0);
  const double sp = 0.01 / c, sr = 1.5 * M_PI / 180.0 / c;
  for (int i = 0; i < 3; ++i) out[i * 7] = sp * sp;
  for (int i = 3; i < 6; ++i) out[i * 7] = sr * sr;
}

// A LOST or SEARCHING track is held at its last pose: not a detection.
bool IsDetection(const instance_t& i) {
  return i.track_state != instance_t::LOST && i.track_state != instance_t::SEARCHING;
}

std::string Number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

}  // namespace

Ros2Detections::Ros2Detections(const detections_t& d, const Ros2Naming& naming) {
  char* frame_id = Keep(&strings_, naming.FrameId(d.frame));
  const builtin_interfaces_msg_dds__Time_ stamp = Stamp(d.utime);
  std::size_t n = 0;
  for (const instance_t& i : d.instances) n += IsDetection(i) ? 1 : 0;
  results_.resize(n);
  detections_.resize(n);
  std::size_t k = 0;
  for (const instance_t& i : d.instances) {
    if (!IsDetection(i)) continue;
    vision_msgs_msg_dds__ObjectHypothesisWithPose_& r = results_[k];
    r.hypothesis.class_id = Keep(&strings_, ClassId(i.model_name));
    r.hypothesis.score = i.confidence;
    r.pose.pose.position = {i.trans[0], i.trans[1], i.trans[2]};
    r.pose.pose.orientation = {i.quat[1], i.quat[2], i.quat[3], i.quat[0]};
    Covariance(i.confidence, r.pose.covariance);
    vision_msgs_msg_dds__Detection3D_& det = detections_[k];
    det.header.stamp = stamp;
    det.header.frame_id = frame_id;
    det.results = {1, 1, &r, false};
    det.bbox.center.position = {i.centroid[0], i.centroid[1], i.centroid[2]};
    det.bbox.center.orientation = r.pose.pose.orientation;
    det.bbox.size = {i.size[0], i.size[1], i.size[2]};
    det.id = Keep(&strings_, i.track_id >= 0 ? std::to_string(i.track_id) : "");
    ++k;
  }
  message.header.stamp = stamp;
  message.header.frame_id = frame_id;
  const auto count = static_cast<std::uint32_t>(n);
  message.detections = {count, count, detections_.data(), false};
}

Ros2Fixation::Ros2Fixation(const fixation_t& f, const Ros2Naming& naming)
    : frame_id_(naming.FrameId(f.frame)) {
  message.header.stamp = Stamp(f.utime);
  message.header.frame_id = frame_id_.data();
  message.point = {f.fovea[0], f.fovea[1], f.fovea[2]};
}

Ros2Preview::Ros2Preview(const DecodedPreview& p, const Ros2Naming& naming)
    : frame_id_(naming.camera_frame_id), format_(p.image_format), jpeg_(p.image) {
  const builtin_interfaces_msg_dds__Time_ stamp = Stamp(p.utime);
  // x, y, z as float32 metres, the tag as uint8, padded to 16 bytes a point.
  static char kX[] = "x", kY[] = "y", kZ[] = "z", kTag[] = "tag";
  fields_ = {{kX, 0, 7, 1}, {kY, 4, 7, 1}, {kZ, 8, 7, 1}, {kTag, 12, 2, 1}};
  constexpr std::uint32_t kStep = 16;
  const auto n = static_cast<std::size_t>(p.num_points);
  points_.assign(n * kStep, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      const std::uint8_t* mm = p.points.data() + 6 * i + 2 * a;
      const auto v = static_cast<std::int16_t>(mm[0] | (mm[1] << 8));
      const float metres = static_cast<float>(v) * 0.001f;
      std::memcpy(points_.data() + kStep * i + 4 * a, &metres, 4);
    }
    points_[kStep * i + 12] = p.points[6 * n + i];
  }
  cloud.header.stamp = stamp;
  cloud.header.frame_id = frame_id_.data();
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(n);
  cloud.fields = {4, 4, fields_.data(), false};
  cloud.is_bigendian = false;
  cloud.point_step = kStep;
  cloud.row_step = static_cast<std::uint32_t>(kStep * n);
  const auto bytes = static_cast<std::uint32_t>(points_.size());
  cloud.data = {bytes, bytes, points_.data(), false};
  cloud.is_dense = true;
  image.header.stamp = stamp;
  image.header.frame_id = frame_id_.data();
  image.format = format_.data();
  const auto size = static_cast<std::uint32_t>(jpeg_.size());
  image.data = {size, size, jpeg_.data(), false};
}

bool Ros2Diagnostics::Take(const status_t& s) {
  // Once a second, however often the status comes (service.status_period_s); a status a few
  // milliseconds early still counts as the next second's.
  if (last_utime_ != 0 && s.utime - last_utime_ < 950000) return false;
  last_utime_ = s.utime;
  strings_.clear();
  std::vector<std::pair<std::string, std::string>> figures = {
      {"source_state", s.source_state},
      {"paused", s.paused ? "true" : "false"},
      {"uptime_s", Number(s.uptime_s)},
      {"fps", Number(s.fps)},
      {"frames_in", std::to_string(s.frames_in)},
      {"frames_processed", std::to_string(s.frames_processed)},
      {"frames_dropped", std::to_string(s.frames_dropped)},
      {"frames_skipped", std::to_string(s.frames_skipped)},
      {"frames_unsent", std::to_string(s.frames_unsent)},
      {"source_reconnects", std::to_string(s.source_reconnects)},
      {"commands_accepted", std::to_string(s.commands_accepted)},
      {"commands_rejected", std::to_string(s.commands_rejected)},
      {"lcm_datagrams_dropped", std::to_string(s.lcm_datagrams_dropped)},
      {"fixation_lag_max", std::to_string(s.fixation_lag_max)},
      {"mode", std::to_string(s.mode)}};
  for (const stage_latency_t& st : s.stages) {
    figures.push_back({st.name + "_p50_ms", Number(st.p50_ms)});
    figures.push_back({st.name + "_p99_ms", Number(st.p99_ms)});
  }
  values_.resize(figures.size());
  for (std::size_t i = 0; i < figures.size(); ++i)
    values_[i] = {Keep(&strings_, figures[i].first), Keep(&strings_, figures[i].second)};

  std::string text = s.source_state;
  std::uint8_t level = 0;  // OK
  if (s.source_state.rfind("waiting for device", 0) == 0 ||
      s.source_state.rfind("reconnecting", 0) == 0 || s.source_state.rfind("failed", 0) == 0) {
    level = 2;  // ERROR: no frames come
  } else if (s.paused) {
    level = 1, text = "paused";
  } else if (s.frames_dropped > last_dropped_ || s.frames_unsent > last_unsent_) {
    level = 1, text = "frames dropped or unsent in the last second";
  }
  last_dropped_ = s.frames_dropped;
  last_unsent_ = s.frames_unsent;
  status_.level = level;
  status_.name = Keep(&strings_, "saccaded");
  status_.message = Keep(&strings_, text);
  status_.hardware_id = Keep(&strings_, s.source);
  const auto n = static_cast<std::uint32_t>(values_.size());
  status_.values = {n, n, values_.data(), false};
  message.header.stamp = Stamp(s.utime);
  message.header.frame_id = Keep(&strings_, "");
  message.status = {1, 1, &status_, false};
  return true;
}

Ros2TfStatic::Ros2TfStatic(const RobotFrameOptions& robot, const Ros2Naming& naming,
                           std::int64_t utime)
    : parent_(robot.name), child_(naming.camera_frame_id) {
  const Eigen::Isometry3f X_RC = robot.RobotFromCamera();
  const Eigen::Quaternionf q(X_RC.rotation());
  transform_.header.stamp = Stamp(utime);
  transform_.header.frame_id = parent_.data();
  transform_.child_frame_id = child_.data();
  transform_.transform.translation = {X_RC.translation().x(), X_RC.translation().y(),
                                      X_RC.translation().z()};
  transform_.transform.rotation = {q.x(), q.y(), q.z(), q.w()};
  message.transforms = {1, 1, &transform_, false};
}

std::vector<std::uint8_t> SerializeCdr(const void* sample, const dds_topic_descriptor_t& type) {
  dds_ostreamLE_t os;
  dds_ostreamLE_init(&os, 0, CDR_ENC_VERSION_1);
  dds_stream_writeLE(&os, static_cast<const char*>(sample), type.m_ops);
  std::vector<std::uint8_t> bytes(4 + std::size_t{os.x.m_index}, 0);
  bytes[1] = 0x01;  // CDR_LE, no options
  if (os.x.m_index > 0) std::memcpy(bytes.data() + 4, os.x.m_buffer, os.x.m_index);
  dds_ostreamLE_fini(&os);
  return bytes;
}

namespace {

// The .msg fields of each type Saccade publishes and of the types they use, transcribed from
// ROS 2's packages (comments left out; every type name written in full).
const std::map<std::string, std::string>& MsgFiles() {
  static const std::map<std::string, std::string> files = {
      {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
      {"geometry_msgs/Pose",
       "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n"},
      {"geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose pose\nfloat64[36] covariance\n"},
      {"geometry_msgs/PointStamped", "std_msgs/Header header\ngeometry_msgs/Point point\n"},
      {"geometry_msgs/Transform",
       "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"},
      {"geometry_msgs/TransformStamped",
       "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"},
      {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
      {"vision_msgs/ObjectHypothesis", "string class_id\nfloat64 score\n"},
      {"vision_msgs/ObjectHypothesisWithPose",
       "vision_msgs/ObjectHypothesis hypothesis\ngeometry_msgs/PoseWithCovariance pose\n"},
      {"vision_msgs/BoundingBox3D", "geometry_msgs/Pose center\ngeometry_msgs/Vector3 size\n"},
      {"vision_msgs/Detection3D",
       "std_msgs/Header header\nvision_msgs/ObjectHypothesisWithPose[] results\n"
       "vision_msgs/BoundingBox3D bbox\nstring id\n"},
      {"vision_msgs/Detection3DArray",
       "std_msgs/Header header\nvision_msgs/Detection3D[] detections\n"},
      {"diagnostic_msgs/KeyValue", "string key\nstring value\n"},
      {"diagnostic_msgs/DiagnosticStatus",
       "byte OK=0\nbyte WARN=1\nbyte ERROR=2\nbyte STALE=3\nbyte level\nstring name\n"
       "string message\nstring hardware_id\ndiagnostic_msgs/KeyValue[] values\n"},
      {"diagnostic_msgs/DiagnosticArray",
       "std_msgs/Header header\ndiagnostic_msgs/DiagnosticStatus[] status\n"},
      {"sensor_msgs/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data\n"},
      {"sensor_msgs/PointField",
       "uint8 INT8=1\nuint8 UINT8=2\nuint8 INT16=3\nuint8 UINT16=4\nuint8 INT32=5\n"
       "uint8 UINT32=6\nuint8 FLOAT32=7\nuint8 FLOAT64=8\nstring name\nuint32 offset\n"
       "uint8 datatype\nuint32 count\n"},
      {"sensor_msgs/PointCloud2",
       "std_msgs/Header header\nuint32 height\nuint32 width\nsensor_msgs/PointField[] fields\n"
       "bool is_bigendian\nuint32 point_step\nuint32 row_step\nuint8[] data\nbool is_dense\n"},
  };
  return files;
}

// The package/Type names a .msg body uses, in order of first use.
std::vector<std::string> Uses(const std::string& body) {
  std::vector<std::string> uses;
  std::size_t at = 0;
  while (at < body.size()) {
    const std::size_t end = body.find('\n', at);
    std::string type = body.substr(at, body.find(' ', at) - at);
    at = end + 1;
    if (const std::size_t bracket = type.find('['); bracket != std::string::npos)
      type.erase(bracket);
    if (type.find('/') != std::string::npos) uses.push_back(type);
  }
  return uses;
}

}  // namespace

std::string Ros2MessageDefinition(const std::string& type) {
  std::string name = type;  // "pkg/msg/Type" -> "pkg/Type"
  if (const std::size_t m = name.find("/msg/"); m != std::string::npos) name.erase(m, 4);
  const auto& files = MsgFiles();
  std::string text = files.at(name);
  // Depth first, each dependency once, as rosbag2 writes them.
  std::set<std::string> done = {name};
  std::vector<std::string> pending = Uses(text);
  std::reverse(pending.begin(), pending.end());
  while (!pending.empty()) {
    const std::string next = pending.back();
    pending.pop_back();
    if (!done.insert(next).second) continue;
    const std::string& body = files.at(next);
    text += std::string(80, '=') + "\nMSG: " + next + "\n" + body;
    std::vector<std::string> uses = Uses(body);
    for (auto it = uses.rbegin(); it != uses.rend(); ++it) pending.push_back(*it);
  }
  return text;
}

}  // namespace saccade
