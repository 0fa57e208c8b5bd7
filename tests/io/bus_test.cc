// The LCM bus over a real UDP multicast socket on this host: what goes out is what the types
// say (frames, units, the robot transform), and commands come in checked and converted.
#include "io/lcm/bus.h"
#include "io/sources/frame_source.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <lcm/lcm-cpp.hpp>
#include <saccade/command_t.hpp>
#include <saccade/detections_t.hpp>
#include <saccade/fixation_t.hpp>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

namespace saccade {
namespace {

std::int64_t WallNowUtime() {
  using namespace std::chrono;
  return duration_cast<microseconds>(system_clock::now().time_since_epoch()).count();
}

std::string TestUrl() {
  return "udpm://239.255.76.67:" + std::to_string(7960 + getpid() % 30) + "?ttl=0";
}

// Publishes `m` until `received` holds (LCM over UDP gives no delivery guarantee, and the
// receiver's socket may not be up for the first message).
template <typename Done>
bool Until(Done received, const std::function<void()>& send) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!received()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    send();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

TEST(LcmBus, PublishesPosesInTheRobotFrameWhenAsked) {
  BusOptions options;
  options.url = TestUrl();
  options.commands = saccade::BusOptions::Commands::kOff;
  options.robot.enabled = true;
  options.robot.name = "base_link";
  options.robot.translation_m = Eigen::Vector3f(0.1f, 0.0f, 0.5f);
  options.robot.rotation =
      Eigen::AngleAxisf(static_cast<float>(EIGEN_PI) / 2, Eigen::Vector3f::UnitZ());
  std::string error;
  auto bus = OpenLcmBus(options, &error);
  ASSERT_TRUE(bus) << error;

  lcm::LCM listener(options.url);
  std::optional<saccade::detections_t> got;
  std::optional<saccade::fixation_t> fixation;
  struct Handler {
    std::optional<saccade::detections_t>* d;
    std::optional<saccade::fixation_t>* f;
    void OnD(const lcm::ReceiveBuffer*, const std::string&, const saccade::detections_t* m) {
      *d = *m;
    }
    void OnF(const lcm::ReceiveBuffer*, const std::string&, const saccade::fixation_t* m) {
      *f = *m;
    }
  } handler{&got, &fixation};
  listener.subscribe("SACCADE_DETECTIONS", &Handler::OnD, &handler);
  listener.subscribe("SACCADE_FIXATION", &Handler::OnF, &handler);

  FrameDetections frame;
  frame.capture_utime = 123456;
  const std::int64_t wall_before = WallNowUtime();
  frame.arrival_steady_ns = SteadyNowNs();
  frame.seq = 7;
  frame.fovea_m = Eigen::Vector3f(0, 0, 1);
  frame.models = {"m.pcd"};
  Detection instance;
  instance.model = 0;
  instance.model_to_scene.block<3, 1>(0, 3) = Eigen::Vector3f(1, 0, 2);
  instance.centroid_m = Eigen::Vector3f(1, 0, 2);
  instance.votes = 9;
  instance.confidence = 0.875f;
  instance.colour_agreement = -1;
  instance.track_id = 3;
  instance.track_state = TrackState::kReacquired;
  frame.instances = {instance};
  frame.track_ms = 0.5f;
  Fixation f;
  f.frame_seq = 7;
  f.fovea_m = Eigen::Vector3f(1, 0, 2);
  f.velocity_mps = Eigen::Vector3f(1, 0, 0);
  f.mode = AttentionMode::kTracking;
  ASSERT_TRUE(Until([&] { return got && fixation; },
                    [&] {
                      bus->Publish(frame, f);
                      listener.handleTimeout(10);
                      listener.handleTimeout(10);
                    }));
  EXPECT_EQ(got->frame, "base_link");
  EXPECT_EQ(got->sensor_utime, 123456);  // the sensor's clock
  // utime: when the frame reached the host, on the epoch clock (bot_core's convention).
  EXPECT_GE(got->utime, wall_before - 5000);
  EXPECT_LE(got->utime, WallNowUtime());
  EXPECT_EQ(got->seq, 7);
  ASSERT_EQ(got->num_instances, 1);
  const auto& i = got->instances[0];
  // X_RM = X_RC X_CM: the camera point (1, 0, 2) turned 90 degrees about z, then moved.
  EXPECT_NEAR(i.trans[0], 0.1, 1e-5);
  EXPECT_NEAR(i.trans[1], 1.0, 1e-5);
  EXPECT_NEAR(i.trans[2], 2.5, 1e-5);
  EXPECT_NEAR(i.quat[0], std::cos(EIGEN_PI / 4), 1e-5);  // w
  EXPECT_NEAR(i.quat[3], std::sin(EIGEN_PI / 4), 1e-5);  // z
  EXPECT_NEAR(i.centroid[1], 1.0, 1e-5);
  EXPECT_EQ(i.votes, 9);
  EXPECT_EQ(i.model, 0);
  EXPECT_EQ(i.model_name, "m.pcd");  // the instance's model index names it
  EXPECT_FLOAT_EQ(i.confidence, 0.875f);
  EXPECT_FLOAT_EQ(i.colour_agreement, -1.0f);
  EXPECT_EQ(i.track_id, 3);
  EXPECT_EQ(int(i.track_state), int(saccade::instance_t::RE_ACQUIRED));
  EXPECT_EQ(i.track_state_name, "RE-ACQUIRED");
  EXPECT_FLOAT_EQ(got->track_ms, 0.5f);
  EXPECT_NEAR(got->fovea[2], 1.5, 1e-5);
  EXPECT_EQ(fixation->frame, "base_link");
  EXPECT_EQ(fixation->sensor_utime, 123456);  // stamped with the frame's capture time
  EXPECT_EQ(fixation->utime, got->utime);     // and the same arrival
  EXPECT_EQ(fixation->seq, 7);
  EXPECT_EQ(fixation->mode_name, "TRACKING");
  EXPECT_NEAR(fixation->velocity[1], 1.0, 1e-5);  // velocities turn but do not move
  EXPECT_NEAR(fixation->velocity[0], 0.0, 1e-5);
}

TEST(LcmBus, CommandsArriveInTheCameraFrameAndBadOnesAreCounted) {
  BusOptions options;
  options.url = TestUrl();
  options.channel_prefix = "ROBOT1";
  options.robot.enabled = true;
  options.robot.translation_m = Eigen::Vector3f(0, 0, 0.5f);
  std::mutex mutex;
  std::vector<Command> commands;
  std::string error;
  auto bus = OpenLcmBus(options, &error);
  ASSERT_TRUE(bus) << error;
  bus->Subscribe([&](const Command& c, const CommandReply& reply) {
    if (c.kind == Command::Kind::kSwitchModel) return reply(false, "no such model");
    std::lock_guard<std::mutex> lock(mutex);
    commands.push_back(c);
    reply(true, "");
  });
  lcm::LCM sender(options.url);
  saccade::command_t look;
  look.kind = saccade::command_t::SET_FOVEA;
  look.fovea[0] = 0.2, look.fovea[1] = 0, look.fovea[2] = 1.5;
  ASSERT_TRUE(Until(
      [&] {
        std::lock_guard<std::mutex> lock(mutex);
        return !commands.empty();
      },
      [&] { sender.publish("ROBOT1_COMMAND", &look); }));
  {
    std::lock_guard<std::mutex> lock(mutex);
    EXPECT_EQ(commands.front().kind, Command::Kind::kSetFovea);
    EXPECT_TRUE(commands.front().fovea_m.isApprox(Eigen::Vector3f(0.2f, 0, 1.0f)));
  }
  const std::int64_t accepted = bus->AcceptedCommands();
  EXPECT_GE(accepted, 1);
  // Wrong channel: ignored, not counted. Bad ones: rejected and counted.
  sender.publish("SACCADE_COMMAND", &look);
  saccade::command_t nan_fovea = look;
  nan_fovea.fovea[0] = std::nan("");
  saccade::command_t model;
  model.kind = saccade::command_t::SWITCH_MODEL;
  model.model = "x.pcd";
  const char short_bytes[] = {1, 2, 3};
  // The receiver is known to be up now: each message is sent once, and counted once.
  const std::vector<std::function<void()>> bad = {
      [&] { sender.publish("ROBOT1_COMMAND", &nan_fovea); },
      [&] { sender.publish("ROBOT1_COMMAND", &model); },
      [&] { sender.publish("ROBOT1_COMMAND", short_bytes, sizeof short_bytes); }};
  for (std::size_t k = 0; k < bad.size(); ++k) {
    bad[k]();
    ASSERT_TRUE(
        Until([&] { return bus->RejectedCommands() == static_cast<std::int64_t>(k + 1); }, [] {}))
        << "bad command " << k;
  }
  EXPECT_EQ(bus->RejectedCommands(), 3);
  EXPECT_EQ(bus->AcceptedCommands(), accepted);
}

TEST(LcmBus, ABadUrlIsOneClearError) {
  BusOptions options;
  options.url = "bogus://nowhere";
  std::string error;
  EXPECT_EQ(OpenLcmBus(options, &error), nullptr);
  EXPECT_NE(error.find("bogus://nowhere"), std::string::npos) << error;
}

}  // namespace
}  // namespace saccade
