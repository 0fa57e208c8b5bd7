// The ROS 2 mirror: Cyclone DDS's writers of the topics of docs/ROS2.md.
#include "core/fail.h"
#include "io/base/log.h"
#include "io/lcm/preview.h"
#include "io/ros2/ros2.h"
#include "io/ros2/ros2_messages.h"

#include <saccade/status_t.hpp>

#include <cstdlib>
#include <ctime>
#include <optional>

namespace saccade {

bool Ros2Built() { return true; }

namespace {

class Ros2Mirror : public MessageMirror {
 public:
  Ros2Mirror(const Ros2Options& options, const RobotFrameOptions& robot, int domain)
      : options_(options),
        robot_(robot),
        domain_(domain),
        naming_{options.camera_frame_id, options.topic_prefix} {}

  ~Ros2Mirror() override {
    if (participant_ > 0) dds_delete(participant_);
  }

  bool Open(std::string* error) {
    participant_ = dds_create_participant(static_cast<dds_domainid_t>(domain_), nullptr, nullptr);
    if (participant_ < 0)
      return Fail(error, "ros2: cannot join DDS domain " + std::to_string(domain_) + ": " +
                             dds_strretcode(participant_) +
                             " (check CYCLONEDDS_URI; docs/ROS2.md)");
    dds_qos_t* qos = Qos();
    detections_ =
        Writer(&vision_msgs_msg_dds__Detection3DArray__desc, naming_.DetectionsTopic(), qos, error);
    fixation_ =
        Writer(&geometry_msgs_msg_dds__PointStamped__desc, naming_.FixationTopic(), qos, error);
    if (options_.diagnostics)
      diagnostics_ =
          Writer(&diagnostic_msgs_msg_dds__DiagnosticArray__desc, "/diagnostics", qos, error);
    dds_delete_qos(qos);
    if (detections_ < 0 || fixation_ < 0 || diagnostics_ < 0) return false;
    return !robot_.enabled || PublishTfStatic(error);
  }

  void Publish(const detections_t& d, const fixation_t& f) override {
    const Ros2Detections detections(d, naming_);
    Write(detections_, &detections.message, "detections");
    const Ros2Fixation fixation(f, naming_);
    Write(fixation_, &fixation.message, "fixation");
  }

  void PublishPreview(const std::vector<std::uint8_t>& encoded) override {
    std::string why;
    const std::optional<DecodedPreview> p = DecodePreview(encoded.data(), encoded.size(), &why);
    if (!p) return;     // made by this process: it decodes
    if (cloud_ == 0) {  // the first preview: previews are on (preview.enabled)
      std::string error;
      dds_qos_t* qos = Qos();
      cloud_ = Writer(&sensor_msgs_msg_dds__PointCloud2__desc, naming_.CloudTopic(), qos, &error);
      image_ =
          Writer(&sensor_msgs_msg_dds__CompressedImage__desc, naming_.ImageTopic(), qos, &error);
      dds_delete_qos(qos);
      if (cloud_ < 0 || image_ < 0) Log(LogLevel::kError, error);
    }
    if (cloud_ < 0 || image_ < 0) return;
    const Ros2Preview preview(*p, naming_);
    Write(cloud_, &preview.cloud, "foveated cloud");
    if (p->image_format == "jpeg") Write(image_, &preview.image, "preview image");
  }

  void PublishStatus(const status_t& s) override {
    if (diagnostics_ > 0 && diagnostics_state_.Take(s))
      Write(diagnostics_, &diagnostics_state_.message, "diagnostics");
  }

  std::string Describe() const override {
    return "ROS 2 on DDS domain " + std::to_string(domain_) + " (" + naming_.DetectionsTopic() +
           ", " + naming_.FixationTopic() + (options_.diagnostics ? ", /diagnostics" : "") + ", " +
           naming_.CloudTopic() + " and " + naming_.ImageTopic() + " with previews" +
           (robot_.enabled ? ", /tf_static" : "") + ")";
  }

 private:
  // ROS 2's default (reliable, volatile, keep last 10) or as configured. The caller deletes it.
  dds_qos_t* Qos() const {
    dds_qos_t* qos = dds_create_qos();
    if (options_.reliable)
      dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    else
      dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, options_.depth);
    return qos;
  }

  // A ROS 2 topic /a/b is the DDS topic rt/a/b.
  dds_entity_t Writer(const dds_topic_descriptor_t* type, const std::string& ros_topic,
                      const dds_qos_t* qos, std::string* error) {
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

  // /tf_static, once, kept for late joiners (transient local, as static_transform_publisher).
  bool PublishTfStatic(std::string* error) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
    dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
    const dds_entity_t writer =
        Writer(&tf2_msgs_msg_dds__TFMessage__desc, "/tf_static", qos, error);
    dds_delete_qos(qos);
    if (writer < 0) return false;
    timespec now{};
    clock_gettime(CLOCK_REALTIME, &now);
    const Ros2TfStatic tf(robot_, naming_, std::int64_t{now.tv_sec} * 1000000 + now.tv_nsec / 1000);
    const dds_return_t rc = dds_write(writer, &tf.message);
    if (rc < 0) return Fail(error, std::string("ros2: /tf_static not sent: ") + dds_strretcode(rc));
    return true;
  }

  const Ros2Options options_;
  const RobotFrameOptions robot_;
  const int domain_;
  const Ros2Naming naming_;
  dds_entity_t participant_ = 0, detections_ = 0, fixation_ = 0, diagnostics_ = 0, cloud_ = 0,
               image_ = 0;
  Ros2Diagnostics diagnostics_state_;
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
