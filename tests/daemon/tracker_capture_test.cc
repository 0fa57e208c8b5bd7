// saccaded's tracker on a real-data sequence (configs/sequences, ../shared/data; skipped
// without it), driven frame by frame with an in-memory bus: tracking, loss and re-acquisition
// through the whole pipeline, against the sequence's exact truth.
#include "core/recognition.h"
#include "daemon/tracker.h"
#include "io/formats/cloud_io.h"
#include "io/lcm/memory_bus.h"
#include "io/sources/frame_source.h"
#include "io/sources/model_source.h"
#include "support/test_data.h"

#include <gtest/gtest.h>

#include <functional>
#include <set>

namespace saccade {
namespace {
const std::string kSourceDir = SACCADE_SOURCE_DIR;
}  // namespace
}  // namespace saccade

namespace saccade {
namespace {

// saccaded's tracker (configs/saccaded.yaml) on sequence `name` with the given models (the
// sequence's object, then its others), every frame processed: the published frames and each
// frame's truth.
struct SequenceRun {
  std::vector<MemoryBus::Published> frames;
  std::vector<GroundTruth> truth;
  std::vector<Eigen::Vector3f> centres;  // each model's centroid, its frame
};
SequenceRun TrackSequence(const std::string& name, const std::vector<int>& others) {
  const std::string sequence = kSourceDir + "/configs/sequences/" + name + ".yaml";
  const std::string data = "?data=" + testing::DataPath("");
  DaemonSettings settings;
  std::string error;
  SequenceRun run;
  EXPECT_TRUE(LoadDaemonSettings(kSourceDir + "/configs/saccaded.yaml", &settings, &error))
      << error;
  settings.models = {"capture:" + sequence + data};
  for (int k : others)
    settings.models.push_back("capture:" + sequence + data + "&object=" + std::to_string(k));
  settings.service.summary = ServiceOptions::Summary::kOff;
  auto bus = std::make_unique<MemoryBus>();
  MemoryBus* published = bus.get();
  auto tracker = Tracker::Create(settings, nullptr, std::move(bus), nullptr, &error);
  EXPECT_TRUE(tracker) << error;
  if (!tracker) return run;
  for (const std::string& spec : settings.models) {
    const std::optional<Cloud> model = LoadModelCloud(spec, &error);
    EXPECT_TRUE(model) << error;
    if (!model) return run;
    run.centres.push_back(FiniteCentroid(*model).value_or(Eigen::Vector3f::Zero()));
  }
  auto source = OpenSource("capture:" + sequence + "?rate=0&" + data.substr(1), &error);
  EXPECT_TRUE(source) << error;
  if (!source) return run;
  Frame f;
  while (source->Next(&f, &error) == FrameSource::Status::kFrame) {
    run.truth.push_back(*f.truth);
    tracker->Process(std::move(f));
  }
  run.frames = published->Frames();
  return run;
}

bool Held(const Detection& d) {
  return d.track_state == TrackState::kTracking || d.track_state == TrackState::kReacquired;
}

// The frames the sequence's object is in view (its truth's visible share >= 0.2), and of those
// the ones a held instance of it is within 2 cm and 5 degrees on; `check` sees the error of
// every held instance, in view or not.
struct InView {
  int visible = 0, within = 0;
};
InView CountInView(const SequenceRun& run,
                   const std::function<void(std::size_t, bool, const PoseError&)>& check) {
  InView out;
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    const bool visible = run.truth[i].visible_fraction >= 0.2f;
    out.visible += visible;
    for (const Detection& d : run.frames[i].frame.instances) {
      if (!Held(d)) continue;
      const PoseError e =
          ComparePoses(d.model_to_scene, run.truth[i].target_pose.matrix(), run.centres[0]);
      check(i, visible, e);
      out.within += visible && e.translation_m < 0.02 && e.rotation_deg < 5;
    }
  }
  return out;
}

// The occluded sequence: a board passes in front of the coffee can for a second (frames
// 30-59). Every pose held is within 2 cm of the truth, the track is LOST within two frames of
// the can being hidden, nothing is held on the board (nor on the look-alike 22.6 cm away,
// confidence 0.84, that recognition finds while the can hides), and the same track is
// re-acquired within 3 frames of the can coming out.
TEST(CaptureTracking, TheTrackerHoldsTheObjectLosesItUnderAnOccluderAndReacquiresIt) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  const SequenceRun run = TrackSequence("occluded", {});
  ASSERT_EQ(run.frames.size(), 90u);
  int hidden = -1, back = -1, lost_at = -1, reacquired_at = -1, held_before = 0;
  std::set<int> ids;
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    const bool visible = run.truth[i].visible_fraction >= 0.2f;
    if (!visible && hidden < 0) hidden = int(i);
    if (visible && hidden >= 0 && back < 0) back = int(i);
    for (const Detection& d : run.frames[i].frame.instances) {
      if (d.track_state == TrackState::kLost && hidden >= 0 && lost_at < 0) lost_at = int(i);
      if (!Held(d)) continue;
      ids.insert(d.track_id);
      EXPECT_TRUE(visible) << "frame " << i << ": held while the can is hidden";
      if (back >= 0 && reacquired_at < 0) reacquired_at = int(i);
      const PoseError e =
          ComparePoses(d.model_to_scene, run.truth[i].target_pose.matrix(), run.centres[0]);
      EXPECT_LT(e.translation_m, 0.02) << "frame " << i << " " << TrackStateName(d.track_state);
      if (back < 0) ++held_before;
    }
  }
  ASSERT_GT(hidden, 0);
  ASSERT_GT(back, hidden);
  EXPECT_GE(lost_at, hidden);
  EXPECT_LE(lost_at, hidden + 2);
  EXPECT_GE(held_before, hidden - 2);  // found on the first frames, held until hidden
  EXPECT_GE(reacquired_at, back);
  EXPECT_LE(reacquired_at, back + 3);
  EXPECT_EQ(ids.size(), 1u);  // one track, one id, before and after
}

// The two-objects sequence: the can slides while object 4 (a look-alike of it: each model is
// found on the other object at confidence 0.66-0.84) stands. Both are tracked, each by one
// track with its own id, never on the other object; each is held within 2 cm on at least 80%
// of the frames.
TEST(CaptureTracking, TwoObjectsAreTrackedAtOnceEachWithItsOwnId) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  const SequenceRun run = TrackSequence("two-objects", {4});
  ASSERT_EQ(run.frames.size(), 90u);
  std::vector<std::set<int>> ids(2);
  std::vector<int> within(2, 0);
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    ASSERT_EQ(run.truth[i].others.size(), 1u);
    for (const Detection& d : run.frames[i].frame.instances) {
      if (!Held(d)) continue;
      ASSERT_TRUE(d.model == 0 || d.model == 1);
      const Eigen::Isometry3f& truth =
          d.model == 0 ? run.truth[i].target_pose : run.truth[i].others[0].pose;
      const PoseError e =
          ComparePoses(d.model_to_scene, truth.matrix(), run.centres[std::size_t(d.model)]);
      EXPECT_LT(e.translation_m, 0.05) << "frame " << i << " model " << d.model;
      ids[std::size_t(d.model)].insert(d.track_id);
      if (e.translation_m < 0.02) ++within[std::size_t(d.model)];
    }
  }
  EXPECT_EQ(ids[0].size(), 1u);
  EXPECT_EQ(ids[1].size(), 1u);
  EXPECT_NE(*ids[0].begin(), *ids[1].begin());
  EXPECT_GE(within[0], 72);
  EXPECT_GE(within[1], 72);
}

// The two-objects sequence with the can alone tracked: the can slides out of the image's left
// edge while the camera drifts (its centre leaves the image at frame 74). While less than half
// of it is in the image the tracker holds its turn (tracking.min_in_image_to_turn; at 0 the
// turn drifts 6.6 degrees by frame 79). Every frame it is in view is held within 2 cm and 5
// degrees. Once less than 15% of it is in the image the track is LOST (it was held on the
// sliver for 5 frames after the truth said the can was gone): within 2 frames of that.
TEST(CaptureTracking, AnObjectLeavingAtTheImagesEdgeIsHeldWithoutTurning) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  const SequenceRun run = TrackSequence("two-objects", {});
  ASSERT_EQ(run.frames.size(), 90u);
  int held_while_gone = 0;
  const InView seen = CountInView(run, [&](std::size_t i, bool visible, const PoseError& e) {
    if (visible) {
      EXPECT_LT(e.rotation_deg, 5) << "frame " << i;
    } else {
      ++held_while_gone;
    }
  });
  EXPECT_EQ(seen.visible, 80);
  EXPECT_EQ(seen.within, seen.visible);
  EXPECT_LE(held_while_gone, 2);
}

// The object-leave-return sequence: the coffee can leaves the view at 1 m/s (3.3 cm a frame)
// and comes back. Found standing still as far as tracking knows, the can is outrun: tracking from
// its found pose lags it by 2-4 cm and turns it 30-65 degrees about its axis, and the re-check on
// the next frame confirmed that lagging pose. The first two sightings by recognition now give the
// track its motion: of the 19 frames it is in view, the tracker held it within 2 cm and 5
// degrees on 16 (5 before), and never 5 cm off. The three it missed were its return at the
// image's edge, 71 frames after it left, where recognition does not find it yet: its track is
// now re-acquired where it was lost, its turn held (tracking.watch_lost_frames), and every
// frame it is in view is held.
TEST(CaptureTracking, AFastObjectIsHeldFromItsFirstTwoSightings) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  const SequenceRun run = TrackSequence("object-leave-return", {});
  ASSERT_EQ(run.frames.size(), 90u);
  const InView seen = CountInView(run, [](std::size_t i, bool, const PoseError& e) {
    EXPECT_LT(e.translation_m, 0.05) << "frame " << i;
  });
  EXPECT_EQ(seen.visible, 19);
  EXPECT_EQ(seen.within, seen.visible);
}

}  // namespace
}  // namespace saccade
