// What publishing a frame costs (make bench): a frame of three tracked objects sent by the
// LCM bus over UDP multicast (ttl=0) alone, and with the ROS 2 mirror beside it (Cyclone DDS,
// a ROS 2 reader of every topic in this process, as a node on the same host would be). Both
// in the same run, so that their ratio holds on a busy machine. A benchmark, not a test.
#include "core/types.h"
#include "io/lcm/bus.h"
#include "io/ros2/ros2.h"

#include <benchmark/benchmark.h>
#include <dds/dds.h>

#include "vision_msgs.h"

#include <cstdio>
#include <cstdlib>

namespace saccade {
namespace {

FrameDetections ThreeObjects() {
  FrameDetections f;
  f.seq = 1;
  f.models = {"/var/lib/saccade/models/can.pcd", "/var/lib/saccade/models/box.pcd",
              "/var/lib/saccade/models/mug.pcd"};
  f.model_extents_m = {{0.07f, 0.07f, 0.12f}, {0.1f, 0.05f, 0.2f}, {0.09f, 0.09f, 0.1f}};
  for (int m = 0; m < 3; ++m) {
    Detection d;
    d.model = m;
    d.model_to_scene.block<3, 1>(0, 3) = Eigen::Vector3f(0.1f * m, 0.0f, 0.8f);
    d.centroid_m = Eigen::Vector3f(0.1f * m, 0.02f, 0.8f);
    d.votes = 40;
    d.confidence = 0.9f;
    d.fitness = d.coverage = 0.8f;
    d.track_id = m;
    d.track_state = TrackState::kTracking;
    f.instances.push_back(d);
  }
  return f;
}

void Publish(benchmark::State& state, std::unique_ptr<MessageMirror> mirror) {
  BusOptions options;
  options.url = "udpm://239.255.76.67:7669?ttl=0";
  options.commands = BusOptions::Commands::kOff;
  std::string error;
  std::vector<std::unique_ptr<MessageMirror>> mirrors;
  if (mirror) mirrors.push_back(std::move(mirror));
  std::unique_ptr<Bus> bus = OpenLcmBus(options, &error, std::move(mirrors));
  if (!bus) {
    state.SkipWithError(error.c_str());
    return;
  }
  FrameDetections frame = ThreeObjects();
  Fixation fixation;
  for (auto _ : state) {
    ++frame.seq;
    benchmark::DoNotOptimize(bus->Publish(frame, fixation));
  }
}

void BM_PublishLcm(benchmark::State& state) { Publish(state, nullptr); }
BENCHMARK(BM_PublishLcm)->Unit(benchmark::kMicrosecond);

void BM_PublishLcmAndRos2(benchmark::State& state) {
  setenv("ROS_DOMAIN_ID", "231", 1);  // a domain of its own
  std::string error;
  std::unique_ptr<MessageMirror> mirror =
      OpenRos2Mirror(Ros2Options{}, RobotFrameOptions{}, &error);
  if (!mirror) {
    state.SkipWithError(error.c_str());
    return;
  }
  // A ROS 2 node's reader of the detections on this host, taking what arrives.
  const dds_entity_t participant = dds_create_participant(231, nullptr, nullptr);
  const dds_entity_t topic =
      dds_create_topic(participant, &vision_msgs_msg_dds__Detection3DArray__desc,
                       "rt/saccade/detections", nullptr, nullptr);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
  dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  Publish(state, std::move(mirror));
  dds_delete(participant);
}
BENCHMARK(BM_PublishLcmAndRos2)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace saccade

BENCHMARK_MAIN();
