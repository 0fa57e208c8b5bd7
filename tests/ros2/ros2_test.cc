// saccaded --ros2 heard as a ROS 2 node hears it: the DDS topics rt/saccade/detections,
// rt/saccade/fixation and rt/diagnostics under ROS 2's type names, read with ROS 2's types
// alone (io/ros2/idl compiled by idlc; none of Saccade's code), each message checked against
// the LCM message saccaded sent for the same frame.
#include "support/processes.h"
#include "support/small_disk.h"

#include <dds/dds.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <lcm/lcm-cpp.hpp>
#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>

#include "diagnostic_msgs.h"
#include "geometry_msgs.h"
#include "sensor_msgs.h"
#include "tf2_msgs.h"
#include "vision_msgs.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <string>
#include <vector>

namespace {

using saccade::testing::Child;
using saccade::testing::ReadFile;
using saccade::testing::Sandbox;
using saccade::testing::Spawn;

const std::string kSaccaded = SACCADED_BINARY;
const std::string kSaccade = SACCADE_BINARY;
const std::string kSourceDir = SACCADE_SOURCE_DIR;

std::int64_t Utime(const builtin_interfaces_msg_dds__Time_& t) {
  return std::int64_t{t.sec} * 1000000 + t.nanosec / 1000;
}

struct Instance {
  std::string class_id, id;
  double score = 0;
  double position[3], orientation[4], covariance[36], center[3], center_orientation[4], size[3];
};
struct Frame {
  std::string frame_id;
  std::vector<Instance> instances;
};
struct Diagnostic {
  int level = -1;
  std::string name, hardware_id;
  std::map<std::string, std::string> values;
};

// A ROS 2 subscriber's reader: reliable, keeping every sample.
class Reader {
 public:
  Reader(dds_entity_t participant, const dds_topic_descriptor_t* type, const std::string& topic,
         bool transient_local = false) {
    const dds_entity_t t = dds_create_topic(participant, type, topic.c_str(), nullptr, nullptr);
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
    dds_qset_durability(qos,
                        transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
    reader_ = dds_create_reader(participant, t, qos, nullptr);
    dds_delete_qos(qos);
    EXPECT_GT(reader_, 0) << dds_strretcode(reader_);
  }
  // Calls `on` with every sample taken now; how many.
  template <typename T, typename F>
  int Take(F on) {
    void* samples[64] = {nullptr};
    dds_sample_info_t infos[64];
    const dds_return_t n = dds_take(reader_, samples, infos, 64, 64);
    for (int i = 0; i < n; ++i)
      if (infos[i].valid_data) on(*static_cast<const T*>(samples[i]));
    if (n > 0) dds_return_loan(reader_, samples, n);
    return n > 0 ? n : 0;
  }

 private:
  dds_entity_t reader_ = -1;
};

struct Heard {
  std::map<std::int64_t, Frame> detections;  // by header stamp, microseconds
  std::map<std::int64_t, std::vector<double>> fixations;
  std::map<std::int64_t, std::string> fixation_frames;
  std::vector<Diagnostic> diagnostics;
  std::vector<std::uint32_t> cloud_points;  // each foveated cloud's
  int images = 0;
};

struct Ros2Listener {
  explicit Ros2Listener(int domain)
      : participant(dds_create_participant(static_cast<dds_domainid_t>(domain), nullptr, nullptr)),
        detections(participant, &vision_msgs_msg_dds__Detection3DArray__desc,
                   "rt/saccade/detections"),
        fixation(participant, &geometry_msgs_msg_dds__PointStamped__desc, "rt/saccade/fixation"),
        diagnostics(participant, &diagnostic_msgs_msg_dds__DiagnosticArray__desc, "rt/diagnostics"),
        cloud(participant, &sensor_msgs_msg_dds__PointCloud2__desc, "rt/saccade/foveated_cloud"),
        image(participant, &sensor_msgs_msg_dds__CompressedImage__desc,
              "rt/saccade/preview/compressed") {}
  ~Ros2Listener() { dds_delete(participant); }

  int Take(Heard* h) {
    int n = detections.Take<vision_msgs_msg_dds__Detection3DArray_>([&](const auto& m) {
      Frame& f = h->detections[Utime(m.header.stamp)];
      f.frame_id = m.header.frame_id;
      for (std::uint32_t k = 0; k < m.detections._length; ++k) {
        const vision_msgs_msg_dds__Detection3D_& d = m.detections._buffer[k];
        EXPECT_EQ(Utime(d.header.stamp), Utime(m.header.stamp));
        EXPECT_EQ(d.results._length, 1u);
        if (d.results._length != 1) continue;
        const auto& r = d.results._buffer[0];
        Instance i;
        i.class_id = r.hypothesis.class_id;
        i.score = r.hypothesis.score;
        i.id = d.id;
        const auto& p = r.pose.pose;
        double pos[3] = {p.position.x, p.position.y, p.position.z};
        double q[4] = {p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w};
        std::copy(pos, pos + 3, i.position);
        std::copy(q, q + 4, i.orientation);
        std::copy(r.pose.covariance, r.pose.covariance + 36, i.covariance);
        const auto& c = d.bbox.center;
        double center[3] = {c.position.x, c.position.y, c.position.z};
        double cq[4] = {c.orientation.x, c.orientation.y, c.orientation.z, c.orientation.w};
        double size[3] = {d.bbox.size.x, d.bbox.size.y, d.bbox.size.z};
        std::copy(center, center + 3, i.center);
        std::copy(cq, cq + 4, i.center_orientation);
        std::copy(size, size + 3, i.size);
        f.instances.push_back(i);
      }
    });
    n += fixation.Take<geometry_msgs_msg_dds__PointStamped_>([&](const auto& m) {
      h->fixations[Utime(m.header.stamp)] = {m.point.x, m.point.y, m.point.z};
      h->fixation_frames[Utime(m.header.stamp)] = m.header.frame_id;
    });
    n += diagnostics.Take<diagnostic_msgs_msg_dds__DiagnosticArray_>([&](const auto& m) {
      for (std::uint32_t k = 0; k < m.status._length; ++k) {
        const auto& s = m.status._buffer[k];
        Diagnostic d;
        d.level = s.level;
        d.name = s.name;
        d.hardware_id = s.hardware_id;
        for (std::uint32_t v = 0; v < s.values._length; ++v)
          d.values[s.values._buffer[v].key] = s.values._buffer[v].value;
        h->diagnostics.push_back(d);
      }
    });
    n += cloud.Take<sensor_msgs_msg_dds__PointCloud2_>([&](const auto& m) {
      EXPECT_EQ(m.point_step, 16u);
      EXPECT_EQ(m.data._length, m.width * 16u);
      EXPECT_EQ(m.fields._length, 4u);
      h->cloud_points.push_back(m.width);
    });
    n += image.Take<sensor_msgs_msg_dds__CompressedImage_>([&](const auto& m) {
      EXPECT_STREQ(m.format, "jpeg");
      EXPECT_GT(m.data._length, 1000u);
      ++h->images;
    });
    return n;
  }

  dds_entity_t participant;
  Reader detections, fixation, diagnostics, cloud, image;
};

// What saccaded sent over LCM.
struct LcmHeard {
  std::map<std::int64_t, saccade::detections_t> detections;
  std::map<std::int64_t, saccade::fixation_t> fixations;
  void OnDetections(const lcm::ReceiveBuffer*, const std::string&, const saccade::detections_t* m) {
    detections[m->utime] = *m;
  }
  void OnFixation(const lcm::ReceiveBuffer*, const std::string&, const saccade::fixation_t* m) {
    fixations[m->utime] = *m;
  }
};

bool Exited(pid_t pid) {
  siginfo_t info{};
  return waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
         info.si_pid == pid;
}

// A DDS domain of this test's own, so that tests run side by side do not hear each other.
int Domain() { return 100 + getpid() % 100; }

// saccaded on the synthetic demo (120 frames at 30 Hz, then it exits) with --ros2: every frame
// after discovery arrives on ROS 2 as on LCM, field for field.
TEST(Ros2, EveryFrameOnRos2MatchesItsLcmMessageFieldForField) {
  Sandbox box;
  const int domain = Domain();
  Ros2Listener ros2(domain);
  lcm::LCM lcm(box.url);
  ASSERT_TRUE(lcm.good());
  LcmHeard sent;
  lcm.subscribe("SACCADE_DETECTIONS", &LcmHeard::OnDetections, &sent);
  lcm.subscribe("SACCADE_FIXATION", &LcmHeard::OnFixation, &sent);
  Child daemon = Spawn(
      {kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--source",
       "synthetic:" + kSourceDir + "/configs/demo-scenario.yaml", "--lcm-url", box.url, "--ros2"},
      box.Path("out"), box.Path("err"), {"ROS_DOMAIN_ID=" + std::to_string(domain)});
  Heard heard;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (!Exited(daemon.Pid()) && std::chrono::steady_clock::now() < deadline) {
    lcm.handleTimeout(20);
    ros2.Take(&heard);
  }
  ASSERT_EQ(daemon.Wait().code, 0) << ReadFile(box.Path("err"));
  while (lcm.handleTimeout(50) > 0) {
  }
  // What was written before the exit and is still on its way (a writer lingers until acked).
  for (int quiet = 0; quiet<25; quiet = ros2.Take(&heard)> 0 ? 0 : quiet + 1) lcm.handleTimeout(20);

  ASSERT_FALSE(heard.detections.empty()) << ReadFile(box.Path("err"));
  const std::int64_t discovered = heard.detections.begin()->first;
  int after = 0, matched = 0, instances = 0;
  for (const auto& [utime, d] : sent.detections) {
    if (utime < discovered) continue;
    ++after;
    const auto it = heard.detections.find(utime);
    if (it == heard.detections.end()) continue;
    ++matched;
    const Frame& f = it->second;
    EXPECT_EQ(f.frame_id, d.frame);
    std::vector<const saccade::instance_t*> seen;
    for (const saccade::instance_t& i : d.instances)
      if (i.track_state != saccade::instance_t::LOST &&
          i.track_state != saccade::instance_t::SEARCHING)
        seen.push_back(&i);
    ASSERT_EQ(f.instances.size(), seen.size()) << "frame " << d.seq;
    for (std::size_t k = 0; k < seen.size(); ++k) {
      const saccade::instance_t& l = *seen[k];
      const Instance& r = f.instances[k];
      ++instances;
      EXPECT_EQ(r.class_id, "target");  // synthetic:target
      EXPECT_EQ(r.id, l.track_id >= 0 ? std::to_string(l.track_id) : "");
      EXPECT_EQ(r.score, static_cast<double>(l.confidence));
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(r.position[a], l.trans[a]);
        EXPECT_EQ(r.center[a], l.centroid[a]);
        EXPECT_GT(r.size[a], 0.02);  // the target is a box of several centimetres
        EXPECT_LT(r.size[a], 0.5);
      }
      for (int a = 0; a < 3; ++a) EXPECT_EQ(r.orientation[a], l.quat[a + 1]);  // x y z
      EXPECT_EQ(r.orientation[3], l.quat[0]);                                  // w
      for (int a = 0; a < 4; ++a) EXPECT_EQ(r.center_orientation[a], r.orientation[a]);
      for (int a = 0; a < 6; ++a) EXPECT_GT(r.covariance[a * 7], 0.0);
      EXPECT_EQ(r.covariance[1], 0.0);
    }
  }
  std::printf("ROS 2: %d of %d frames after discovery, %d instances, %zu diagnostics\n", matched,
              after, instances, heard.diagnostics.size());
  EXPECT_GE(after, 100);
  EXPECT_GE(matched * 100, after * 99) << matched << " of " << after << " frames on ROS 2";
  EXPECT_GE(instances, 50);  // the demo's target is seen in most frames

  int fixations = 0;
  for (const auto& [utime, f] : sent.fixations) {
    const auto it = heard.fixations.find(utime);
    if (utime < discovered || it == heard.fixations.end()) continue;
    ++fixations;
    for (int a = 0; a < 3; ++a) EXPECT_EQ(it->second[static_cast<std::size_t>(a)], f.fovea[a]);
    EXPECT_EQ(heard.fixation_frames[utime], f.frame);
  }
  EXPECT_GE(fixations * 100, after * 99);

  ASSERT_GE(heard.diagnostics.size(), 2u);  // once a second over a four-second run
  const Diagnostic& last = heard.diagnostics.back();
  EXPECT_EQ(last.name, "saccaded");
  EXPECT_EQ(last.hardware_id, "synthetic:" + kSourceDir + "/configs/demo-scenario.yaml");
  EXPECT_LE(last.level, 1);
  EXPECT_EQ(last.values.count("frames_processed"), 1u);
  EXPECT_EQ(last.values.count("recognize_p50_ms"), 1u);

  // demo.yaml turns previews on (5 a second over four seconds): each as a cloud and an image.
  EXPECT_GE(heard.cloud_points.size(), 10u);
  EXPECT_EQ(heard.images, static_cast<int>(heard.cloud_points.size()));
  for (std::uint32_t n : heard.cloud_points) EXPECT_GT(n, 100u);
}

// With a robot frame: detections in it, and /tf_static (transient local) handing a subscriber
// that joins late the camera's place in it, as a static_transform_publisher would.
TEST(Ros2, WithARobotFrameALateSubscriberGetsTfStatic) {
  Sandbox box;
  const int domain = 1 + getpid() % 99;  // not Domain(): the other tests may run beside it
  std::string config = ReadFile(kSourceDir + "/configs/demo.yaml");
  config +=
      "robot_frame:\n  enabled: true\n  name: base_link\n"
      "  translation_m: [0.1, 0.0, 0.5]\n  rotation: [1, 0, 0, 0]\n"
      "ros2:\n  camera_frame_id: head_camera\n";
  std::ofstream(box.Path("robot.yaml")) << config;
  Ros2Listener ros2(domain);
  Child daemon =
      Spawn({kSaccaded, "--config", box.Path("robot.yaml"), "--source",
             "synthetic:static?rate=10&loop=1", "--lcm-url", box.url, "--ros2"},
            box.Path("out"), box.Path("err"), {"ROS_DOMAIN_ID=" + std::to_string(domain)});
  Heard heard;
  ASSERT_TRUE(saccade::testing::WaitFor([&] {
    ros2.Take(&heard);
    return !heard.detections.empty();
  })) << ReadFile(box.Path("err"));
  EXPECT_EQ(heard.detections.begin()->second.frame_id, "base_link");
  // A subscriber that comes after the transform was sent.
  Reader tf(ros2.participant, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf_static",
            /*transient_local=*/true);
  std::vector<std::string> got;
  ASSERT_TRUE(saccade::testing::WaitFor(
      [&] {
        tf.Take<tf2_msgs_msg_dds__TFMessage_>([&](const auto& m) {
          for (std::uint32_t k = 0; k < m.transforms._length; ++k) {
            const auto& t = m.transforms._buffer[k];
            char line[200];
            std::snprintf(line, sizeof line, "%s -> %s (%.2f, %.2f, %.2f) w %.2f",
                          t.header.frame_id, t.child_frame_id, t.transform.translation.x,
                          t.transform.translation.y, t.transform.translation.z,
                          t.transform.rotation.w);
            got.push_back(line);
          }
        });
        return !got.empty();
      },
      30));
  EXPECT_EQ(got, std::vector<std::string>{"base_link -> head_camera (0.10, 0.00, 0.50) w 1.00"});
  daemon.Signal(SIGTERM);
  EXPECT_EQ(daemon.Wait().code, 0) << ReadFile(box.Path("err"));
}

// A ROS_DOMAIN_ID a ROS 2 node would refuse stops saccaded with one line and exit code 1.
TEST(Ros2, ABadDomainIdIsOneLineAndExitOne) {
  Sandbox box;
  Child daemon = Spawn(
      {kSaccaded, "--config", kSourceDir + "/configs/demo.yaml", "--lcm-url", box.url, "--ros2"},
      box.Path("out"), box.Path("err"), {"ROS_DOMAIN_ID=300"});
  EXPECT_EQ(daemon.Wait().code, 1);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("ROS_DOMAIN_ID must be a whole number from 0 to 232 (it is '300')"),
            std::string::npos)
      << err;
  EXPECT_EQ(saccade::testing::Count(err, "\n"), 1) << err;
}

// An lcm-logger log of `frames` frames of saccaded's detections (an instance each, as large
// as a real one) and fixations, written with liblcm's own log writer.
void WriteLog(const std::string& path, int frames) {
  lcm::LogFile log(path, "w");
  ASSERT_TRUE(log.good());
  for (int k = 0; k < frames; ++k) {
    saccade::detections_t d{};
    d.utime = 1796400000000000 + k * 33333;
    d.seq = k;
    d.frame = "camera";
    saccade::instance_t i{};
    i.utime = d.utime;
    i.model_name = "/var/lib/saccade/models/mug.pcd";
    i.trans[2] = 0.8;
    i.quat[0] = 1;
    i.size[0] = i.size[1] = i.size[2] = 0.1;
    i.confidence = 0.9f;
    i.track_id = 0;
    i.track_state = saccade::instance_t::TRACKING;
    i.track_state_name = "TRACKING";
    d.instances.push_back(i);
    d.num_instances = 1;
    saccade::fixation_t f{};
    f.utime = d.utime;
    f.frame = "camera";
    f.mode_name = "TRACKING";
    f.reason = "detected";
    for (const auto& [channel, bytes] :
         {std::pair<std::string, std::vector<char>>{"SACCADE_DETECTIONS",
                                                    std::vector<char>(d.getEncodedSize())},
          {"SACCADE_FIXATION", std::vector<char>(f.getEncodedSize())}}) {
      std::vector<char> data = bytes;
      if (channel == "SACCADE_DETECTIONS")
        d.encode(data.data(), 0, static_cast<int>(data.size()));
      else
        f.encode(data.data(), 0, static_cast<int>(data.size()));
      lcm::LogEvent e{};
      e.eventnum = 2 * k + (channel == "SACCADE_FIXATION");
      e.timestamp = d.utime;
      e.channel = channel;
      e.datalen = static_cast<std::int32_t>(data.size());
      e.data = data.data();
      log.writeEvent(&e);
    }
  }
}

// saccade mcap onto a disk that fills: one line saying so, exit 1, no file (nor its .part).
TEST(Mcap, OnAFullDiskItSaysSoExitsOneAndLeavesNoFile) {
  Sandbox box;
  const std::string log = box.Path("run.lcmlog");
  WriteLog(log, 3000);
  saccade::testing::SmallDisk disk(box.Path("disk"), "1M");
  if (!disk.mounted()) GTEST_SKIP() << "needs root to mount a small tmpfs";
  disk.Fill(64);
  const std::string out = disk.dir() + "/run.mcap";
  Child c = Spawn({kSaccade, "mcap", log, "-o", out}, box.Path("out"), box.Path("err"));
  EXPECT_EQ(c.Wait().code, 1);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("No space left on device"), std::string::npos) << err;
  EXPECT_EQ(saccade::testing::Count(err, "\n"), 1) << err;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_FALSE(std::filesystem::exists(out + ".part"));
  // With room, the same log converts whole.
  Child ok =
      Spawn({kSaccade, "mcap", log, "-o", box.Path("run.mcap")}, box.Path("out"), box.Path("err"));
  EXPECT_EQ(ok.Wait().code, 0) << ReadFile(box.Path("err"));
  EXPECT_NE(ReadFile(box.Path("out")).find("3000 detections, 3000 fixations"), std::string::npos)
      << ReadFile(box.Path("out"));
}

// What is not an lcm-logger log is refused before anything is written.
TEST(Mcap, NotALogIsOneLineAndNoFile) {
  Sandbox box;
  std::ofstream(box.Path("notes.txt")) << "not a log\n";
  Child c = Spawn({kSaccade, "mcap", box.Path("notes.txt"), "-o", box.Path("x.mcap")},
                  box.Path("out"), box.Path("err"));
  EXPECT_EQ(c.Wait().code, 1);
  const std::string err = ReadFile(box.Path("err"));
  EXPECT_NE(err.find("not an lcm-logger log"), std::string::npos) << err;
  EXPECT_EQ(saccade::testing::Count(err, "\n"), 1) << err;
  EXPECT_FALSE(std::filesystem::exists(box.Path("x.mcap")));
  EXPECT_FALSE(std::filesystem::exists(box.Path("x.mcap.part")));
}

}  // namespace
