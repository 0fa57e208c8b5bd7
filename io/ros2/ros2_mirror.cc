// The ROS 2 mirror over Cyclone DDS's C API, with the ROS 2 types idlc generates from idl/.
#include "core/fail.h"
#include "io/log.h"
#include "io/ros2/ros2.h"

#include <dds/dds.h>
#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>
#include <saccade/status_t.hpp>

#include "diagnostic_msgs.h"
#include "geometry_msgs.h"
#include "tf2_msgs.h"
#include "vision_msgs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <vector>

namespace saccade {

bool Ros2Built() { return true; }

namespace {

// ROS 2 strings are char*; the messages only borrow them for the write.
char* Str(const std::string& s) { return const_cast<char*>(s.c_str()); }

builtin_interfaces_msg_dds__Time_ Stamp(std::int64_t utime) {
  builtin_interfaces_msg_dds__Time_ t{};
  const std::int64_t sec = utime >= 0 ? utime / 1000000 : -((-utime + 999999) / 1000000);
  t.sec = static_cast<std::int32_t>(sec);
  t.nanosec = static_cast<std::uint32_t>((utime - sec * 1000000) * 1000);
  return t;
}

// A model's name as ROS 2 users label it: its file name without folder or extension
// ("/var/lib/saccade/models/mug.pcd" -> "mug", "synthetic:target" -> "target").
std::string ClassId(const std::string& spec) {
  std::string name =
      spec.substr(spec.find_last_of("/:") == std::string::npos ? 0 : spec.find_last_of("/:") + 1);
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

bool IsDetection(std::int8_t state) {
  return state != instance_t::LOST && state != instance_t::SEARCHING;
}

class Ros2Mirror : public MessageMirror {
 public:
  Ros2Mirror(const Ros2Options& options, const RobotFrameOptions& robot, int domain)
      : options_(options), robot_(robot), domain_(domain) {}

  ~Ros2Mirror() override {
    if (participant_ > 0) dds_delete(participant_);
  }

  bool Open(std::string* error) {
    participant_ = dds_create_participant(static_cast<dds_domainid_t>(domain_), nullptr, nullptr);
    if (participant_ < 0)
      return Fail(error, std::string("ros2: cannot join DDS domain ") + std::to_string(domain_) +
                             ": " + dds_strretcode(participant_) +
                             " (check CYCLONEDDS_URI; docs/ROS2.md)");
    dds_qos_t* qos = dds_create_qos();
    if (options_.reliable)
      dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    else
      dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, options_.depth);
    detections_ = Writer(&vision_msgs_msg_dds__Detection3DArray__desc,
                         options_.topic_prefix + "/detections", qos, error);
    fixation_ = Writer(&geometry_msgs_msg_dds__PointStamped__desc,
                       options_.topic_prefix + "/fixation", qos, error);
    if (options_.diagnostics)
      diagnostics_ =
          Writer(&diagnostic_msgs_msg_dds__DiagnosticArray__desc, "/diagnostics", qos, error);
    dds_delete_qos(qos);
    if (detections_ < 0 || fixation_ < 0 || diagnostics_ < 0) return false;
    return !robot_.enabled || PublishTfStatic(error);
  }

  void Publish(const detections_t& d, const fixation_t& f,
               const std::vector<Eigen::Vector3f>& extents) override {
    const std::string frame_id = FrameId(d.frame);
    std::vector<std::string> ids, classes;
    std::vector<vision_msgs_msg_dds__ObjectHypothesisWithPose_> results;
    std::vector<vision_msgs_msg_dds__Detection3D_> detections;
    for (const instance_t& i : d.instances) {
      if (!IsDetection(i.track_state)) continue;
      ids.push_back(i.track_id >= 0 ? std::to_string(i.track_id) : "");
      classes.push_back(ClassId(i.model_name));
    }
    results.resize(ids.size());
    detections.resize(ids.size());
    std::size_t k = 0;
    for (const instance_t& i : d.instances) {
      if (!IsDetection(i.track_state)) continue;
      vision_msgs_msg_dds__ObjectHypothesisWithPose_& r = results[k];
      r.hypothesis.class_id = Str(classes[k]);
      r.hypothesis.score = i.confidence;
      r.pose.pose.position = {i.trans[0], i.trans[1], i.trans[2]};
      r.pose.pose.orientation = {i.quat[1], i.quat[2], i.quat[3], i.quat[0]};
      Covariance(i.confidence, r.pose.covariance);
      vision_msgs_msg_dds__Detection3D_& det = detections[k];
      det.header.stamp = Stamp(d.utime);
      det.header.frame_id = Str(frame_id);
      det.results = {1, 1, &r, false};
      det.bbox.center.position = {i.centroid[0], i.centroid[1], i.centroid[2]};
      det.bbox.center.orientation = r.pose.pose.orientation;
      if (i.model >= 0 && static_cast<std::size_t>(i.model) < extents.size()) {
        const Eigen::Vector3f& e = extents[static_cast<std::size_t>(i.model)];
        det.bbox.size = {e.x(), e.y(), e.z()};
      }
      det.id = Str(ids[k]);
      ++k;
    }
    vision_msgs_msg_dds__Detection3DArray_ array{};
    array.header.stamp = Stamp(d.utime);
    array.header.frame_id = Str(frame_id);
    const auto n = static_cast<std::uint32_t>(detections.size());
    array.detections = {n, n, detections.data(), false};
    Write(detections_, &array, "detections");

    geometry_msgs_msg_dds__PointStamped_ point{};
    const std::string fixation_frame = FrameId(f.frame);
    point.header.stamp = Stamp(f.utime);
    point.header.frame_id = Str(fixation_frame);
    point.point = {f.fovea[0], f.fovea[1], f.fovea[2]};
    Write(fixation_, &point, "fixation");
  }

  void PublishStatus(const status_t& s) override {
    // Once a second, however often the status comes (service.status_period_s).
    if (diagnostics_ == 0 ||
        (last_diagnostics_utime_ != 0 && s.utime - last_diagnostics_utime_ < 1000000 - 50000))
      return;
    last_diagnostics_utime_ = s.utime;
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
    std::vector<diagnostic_msgs_msg_dds__KeyValue_> values(figures.size());
    for (std::size_t i = 0; i < figures.size(); ++i)
      values[i] = {Str(figures[i].first), Str(figures[i].second)};

    std::string message = s.source_state;
    std::uint8_t level = 0;  // OK
    if (s.source_state.rfind("waiting for device", 0) == 0 ||
        s.source_state.rfind("reconnecting", 0) == 0 || s.source_state.rfind("failed", 0) == 0) {
      level = 2;  // ERROR: no frames
    } else if (s.paused) {
      level = 1, message = "paused";
    } else if (s.frames_dropped > last_dropped_ || s.frames_unsent > last_unsent_) {
      level = 1, message = "frames dropped or unsent in the last second";
    }
    last_dropped_ = s.frames_dropped;
    last_unsent_ = s.frames_unsent;
    diagnostic_msgs_msg_dds__DiagnosticStatus_ status{};
    status.level = level;
    const std::string name = "saccaded";
    status.name = Str(name);
    status.message = Str(message);
    status.hardware_id = Str(s.source);
    const auto n = static_cast<std::uint32_t>(values.size());
    status.values = {n, n, values.data(), false};
    diagnostic_msgs_msg_dds__DiagnosticArray_ array{};
    array.header.stamp = Stamp(s.utime);
    const std::string empty;
    array.header.frame_id = Str(empty);
    array.status = {1, 1, &status, false};
    Write(diagnostics_, &array, "diagnostics");
  }

  std::string Describe() const override {
    std::string topics = options_.topic_prefix + "/detections, " + options_.topic_prefix +
                         "/fixation" + (options_.diagnostics ? ", /diagnostics" : "") +
                         (robot_.enabled ? ", /tf_static" : "");
    return "ROS 2 on DDS domain " + std::to_string(domain_) + " (" + topics + ")";
  }

 private:
  dds_entity_t Writer(const dds_topic_descriptor_t* type, const std::string& ros_topic,
                      const dds_qos_t* qos, std::string* error) {
    // A ROS 2 topic /a/b is the DDS topic rt/a/b.
    const std::string name = "rt" + ros_topic;
    const dds_entity_t topic = dds_create_topic(participant_, type, name.c_str(), nullptr, nullptr);
    const dds_entity_t writer =
        topic < 0 ? topic : dds_create_writer(participant_, topic, qos, nullptr);
    if (writer < 0)
      Fail(error, "ros2: cannot create the writer of " + ros_topic + ": " + dds_strretcode(writer));
    return writer;
  }

  void Write(dds_entity_t writer, const void* sample, const char* what) {
    const dds_return_t rc = dds_write(writer, sample);
    std::int64_t held_back = 0;
    if (rc < 0 && write_log_.Allow(&held_back))
      Log(LogLevel::kWarning,
          std::string("ros2: ") + what + " not sent: " + dds_strretcode(rc) +
              (held_back > 0 ? " (and " + std::to_string(held_back) + " more not logged)" : ""));
  }

  // /tf_static: the camera in the robot frame, once, kept for late joiners (transient local).
  bool PublishTfStatic(std::string* error) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
    tf_static_ = Writer(&tf2_msgs_msg_dds__TFMessage__desc, "/tf_static", qos, error);
    dds_delete_qos(qos);
    if (tf_static_ < 0) return false;
    const Eigen::Isometry3f X_RC = robot_.RobotFromCamera();
    const Eigen::Quaternionf q(X_RC.rotation());
    geometry_msgs_msg_dds__TransformStamped_ t{};
    struct timespec now {};
    clock_gettime(CLOCK_REALTIME, &now);
    t.header.stamp = Stamp(static_cast<std::int64_t>(now.tv_sec) * 1000000 + now.tv_nsec / 1000);
    t.header.frame_id = Str(robot_.name);
    t.child_frame_id = Str(options_.camera_frame_id);
    t.transform.translation = {X_RC.translation().x(), X_RC.translation().y(),
                               X_RC.translation().z()};
    t.transform.rotation = {q.x(), q.y(), q.z(), q.w()};
    tf2_msgs_msg_dds__TFMessage_ message{};
    message.transforms = {1, 1, &t, false};
    const dds_return_t rc = dds_write(tf_static_, &message);
    if (rc < 0) return Fail(error, std::string("ros2: /tf_static not sent: ") + dds_strretcode(rc));
    return true;
  }

  // LCM names the camera frame "camera"; ROS 2 gets the configured name.
  std::string FrameId(const std::string& lcm_frame) const {
    return !robot_.enabled && lcm_frame == "camera" ? options_.camera_frame_id : lcm_frame;
  }

  static std::string Number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
  }

  const Ros2Options options_;
  const RobotFrameOptions robot_;
  const int domain_;
  dds_entity_t participant_ = 0, detections_ = 0, fixation_ = 0, diagnostics_ = 0, tf_static_ = 0;
  std::int64_t last_diagnostics_utime_ = 0, last_dropped_ = 0, last_unsent_ = 0;
  LogLimiter write_log_{1};
};

}  // namespace

std::unique_ptr<MessageMirror> OpenRos2Mirror(const Ros2Options& options,
                                              const RobotFrameOptions& robot, std::string* error) {
  // ROS_DOMAIN_ID as a ROS 2 node reads it: unset or empty is 0.
  int domain = 0;
  if (const char* env = std::getenv("ROS_DOMAIN_ID"); env && *env) {
    char* end = nullptr;
    const long id = std::strtol(env, &end, 10);
    if (*end != '\0' || id < 0 || id > 232) {
      Fail(error, "ros2: ROS_DOMAIN_ID must be a whole number from 0 to 232 (it is '" +
                      std::string(env).substr(0, 40) + "')");
      return nullptr;
    }
    domain = static_cast<int>(id);
  }
  auto mirror = std::make_unique<Ros2Mirror>(options, robot, domain);
  if (!mirror->Open(error)) return nullptr;
  return mirror;
}

}  // namespace saccade
