// saccaded's tracker on a real-data sequence (configs/sequences, ../shared/data; skipped
// without it), driven frame by frame with an in-memory bus: tracking, loss and re-acquisition
// through the whole pipeline, against the sequence's exact truth.
#include "core/recognition.h"
#include "daemon/tracker.h"
#include "io/cloud_io.h"
#include "io/frame_source.h"
#include "io/memory_bus.h"
#include "support/test_data.h"

#include <gtest/gtest.h>

namespace saccade {
namespace {
const std::string kSourceDir = SACCADE_SOURCE_DIR;
}  // namespace
}  // namespace saccade

namespace saccade {
namespace {

// saccaded's tracker (default settings) on the occluded sequence: a board passes in front of
// the coffee can for a second (frames 30-59). Every pose held before it is within 2 cm of the
// truth, the track is LOST within two frames of the can being hidden, and nothing is held on
// the board. Not asserted, because it does not hold yet: when the can comes out, recognition
// (every frame run here, none dropped) first finds a look-alike 22.6 cm from it (confidence
// 0.84) and the track holds that; at 30 Hz with drops (make bench-track) the can itself is
// re-acquired within 2 frames. docs/BENCHMARKS.md, issue 16's notes.
TEST(CaptureTracking, TheTrackerHoldsTheObjectAndIsLostWithinTwoFramesOfAnOcclusion) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  const std::string sequence = kSourceDir + "/configs/sequences/occluded.yaml";
  DaemonSettings settings;
  std::string error;
  ASSERT_TRUE(LoadDaemonSettings(kSourceDir + "/configs/saccaded.yaml", &settings, &error))
      << error;
  settings.models = {"capture:" + sequence + "?data=" + testing::DataPath("")};
  settings.service.summary = ServiceOptions::Summary::kOff;
  auto bus = std::make_unique<MemoryBus>();
  MemoryBus* published = bus.get();
  auto tracker = Tracker::Create(settings, nullptr, std::move(bus), nullptr, &error);
  ASSERT_TRUE(tracker) << error;
  const std::optional<Cloud> model = LoadModelCloud(settings.models[0], &error);
  ASSERT_TRUE(model) << error;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  for (const PointT& p : *model) centre += p.getVector3fMap();
  centre /= float(model->size());

  auto source = OpenSource("capture:" + sequence + "?rate=0&data=" + testing::DataPath(""), &error);
  ASSERT_TRUE(source) << error;
  std::vector<GroundTruth> truth;
  Frame f;
  while (source->Next(&f, &error) == FrameSource::Status::kFrame) {
    truth.push_back(*f.truth);
    tracker->Process(std::move(f));
  }
  const auto frames = published->Frames();
  ASSERT_EQ(frames.size(), 90u);
  int hidden = -1, back = -1, lost_at = -1, held_before = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const bool visible = truth[i].visible_fraction >= 0.2f;
    if (!visible && hidden < 0) hidden = int(i);
    if (visible && hidden >= 0 && back < 0) back = int(i);
    for (const Detection& d : frames[i].frame.instances) {
      if (d.track_state == TrackState::kLost && hidden >= 0 && lost_at < 0) lost_at = int(i);
      const bool held =
          d.track_state == TrackState::kTracking || d.track_state == TrackState::kReacquired;
      if (!held) continue;
      EXPECT_TRUE(visible) << "frame " << i << ": held while the can is hidden";
      if (back >= 0) continue;  // see above
      const PoseError e = ComparePoses(d.model_to_scene, truth[i].target_pose.matrix(), centre);
      EXPECT_LT(e.translation_m, 0.02) << "frame " << i << " " << TrackStateName(d.track_state);
      ++held_before;
    }
  }
  ASSERT_GT(hidden, 0);
  ASSERT_GT(back, hidden);
  EXPECT_GE(lost_at, hidden);
  EXPECT_LE(lost_at, hidden + 2);
  EXPECT_GE(held_before, hidden - 2);  // found on the first frames, held until hidden
}

}  // namespace
}  // namespace saccade
