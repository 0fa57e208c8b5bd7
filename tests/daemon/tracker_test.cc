// The tracker driven frame by frame, in process, with an in-memory bus: what it publishes for
// each frame of the synthetic Kinect, how commands move it, and model switches and reloads on
// its control thread. saccaded_test.cc runs the same tracker as a process over real LCM.
#include "daemon/tracker.h"

#include "daemon/stages.h"
#include "io/base/clock.h"

#include "io/lcm/memory_bus.h"

#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace saccade {
namespace {

const std::string kSourceDir = SACCADE_SOURCE_DIR;

DaemonSettings DemoSettings() {
  DaemonSettings s;
  std::string error;
  EXPECT_TRUE(LoadDaemonSettings(kSourceDir + "/configs/demo.yaml", &s, &error)) << error;
  s.service.summary = ServiceOptions::Summary::kOff;
  // rate=0: rendered as read, so the test gets every frame (a live source drops late ones).
  s.source.spec = "synthetic:static?frames=6&seed=3&rate=0";
  return s;
}

// A tracker on `settings` publishing to a MemoryBus the test keeps a pointer to.
struct Rig {
  explicit Rig(const DaemonSettings& settings) {
    std::string error;
    std::unique_ptr<FrameSource> source = OpenSource(settings.source.spec, &error);
    EXPECT_TRUE(source) << error;
    frames = OpenSource(settings.source.spec, &error);  // the same frames, for the test to feed
    auto owned = std::make_unique<MemoryBus>();
    bus = owned.get();
    tracker = Tracker::Create(settings, std::move(source), std::move(owned), nullptr, &error);
    EXPECT_TRUE(tracker) << error;
  }
  // Feeds the next frame of the scenario; false at its end.
  bool Step() {
    Frame f;
    std::string error;
    if (frames->Next(&f, &error) != FrameSource::Status::kFrame) return false;
    truths.push_back(f.truth);
    tracker->Process(std::move(f));
    return true;
  }
  std::unique_ptr<FrameSource> frames;
  std::vector<std::optional<GroundTruth>> truths;  // of each frame fed
  MemoryBus* bus = nullptr;
  std::unique_ptr<Tracker> tracker;
};

TEST(Tracker, FindsTheStillTargetAndFollowsItFrameByFrame) {
  Rig rig(DemoSettings());
  ASSERT_TRUE(rig.tracker);
  int steps = 0;
  while (rig.Step()) ++steps;
  ASSERT_EQ(steps, 6);
  const auto published = rig.bus->Frames();
  ASSERT_EQ(published.size(), 6u);
  for (std::size_t i = 0; i < published.size(); ++i) {
    const auto& [frame, fixation] = published[i];
    EXPECT_EQ(frame.seq, static_cast<std::int64_t>(i));
    EXPECT_EQ(fixation.frame_seq, frame.seq);
    ASSERT_EQ(frame.models, std::vector<std::string>{"synthetic:target"});
    // Each frame was foveated at the fixation the one before produced.
    if (i > 0) {
      EXPECT_EQ(frame.fixation_seq, published[i - 1].fixation.frame_seq);
      EXPECT_TRUE(frame.fovea_m.isApprox(published[i - 1].fixation.fovea_m));
    }
  }
  // The target stands still: after the first detection attention follows it, with G_min.
  const auto& last = published.back();
  EXPECT_EQ(last.fixation.mode, AttentionMode::kTracking);
  EXPECT_EQ(last.fixation.growth_m, 0.0f);
  ASSERT_FALSE(last.frame.instances.empty());
  EXPECT_EQ(last.frame.instances[0].model, 0);
  EXPECT_TRUE(last.fixation.fovea_m.isApprox(last.frame.instances[0].centroid_m, 1e-4f));
}

// Issue 34: a cold start with the fovea nowhere near anything (2.5 m away, off to the side).
// The initial fovea is a guess: with no candidate near it, the first frame is recognized at
// the frame's best candidate instead (issue 36: the first frame is not spent where nothing
// is), the next ones at the next candidates, and the first track is on the target. (Here
// the target is the frame's third candidate: frame 2, where it was frame 3 before.) A frame
// that looks at three places (attention.looks_per_frame) finds it in the first frame.
TEST(Tracker, AColdStartLooksAtTheBestCandidateFirstAndItsFirstTrackIsTheTarget) {
  for (const int looks : {1, 3}) {
    DaemonSettings s = DemoSettings();
    s.source.spec = "synthetic:static?frames=10&seed=3&rate=0";
    s.initial_fovea_m = Eigen::Vector3f(0.8f, -0.4f, 2.5f);
    s.attention.looks_per_frame = looks;
    Rig rig(s);
    ASSERT_TRUE(rig.tracker);
    while (rig.Step()) {
    }
    const auto published = rig.bus->Frames();
    ASSERT_EQ(published.size(), 10u);
    ASSERT_EQ(rig.truths.size(), 10u);
    EXPECT_GT((published[0].frame.fovea_m - s.initial_fovea_m).norm(), 1.0f);
    int first_held = -1;
    for (std::size_t i = 0; i < published.size(); ++i) {
      const auto& [frame, fixation] = published[i];
      for (const Detection& d : frame.instances) {
        if (d.track_state != TrackState::kTracking && d.track_state != TrackState::kReacquired)
          continue;
        if (first_held < 0) first_held = static_cast<int>(i);
        ASSERT_TRUE(rig.truths[i]);
        const Eigen::Vector3f in_model =
            Eigen::Isometry3f(d.model_to_scene).inverse() * d.centroid_m;
        EXPECT_LT((d.centroid_m - rig.truths[i]->target_pose * in_model).norm(), 0.03f)
            << looks << " looks, frame " << i << ": a track on something else";
      }
    }
    EXPECT_EQ(first_held, looks == 1 ? 2 : 0) << looks << " looks a frame";
    EXPECT_EQ(published.back().fixation.mode, AttentionMode::kTracking);
  }
}

// pipeline.looks_keep_pace: a live search frame takes a further look only while it would end
// before the next frame arrives. The cold start above, through the stages
// saccaded runs, with the frame's time limit given: unlimited (a source read on demand) and an
// hour away, its first frame looks at the target, the third candidate; spent long ago (a frame
// that waited), it looks only at the first and finds nothing.
TEST(Tracker, ALiveSearchFramePastItsTimeLeavesItsFurtherLooksToTheNextFrame) {
  DaemonSettings s = DemoSettings();
  s.source.spec = "synthetic:static?frames=1&seed=3&rate=0";
  s.initial_fovea_m = Eigen::Vector3f(0.8f, -0.4f, 2.5f);
  std::string error;
  std::unique_ptr<FrameSource> frames = OpenSource(s.source.spec, &error);
  ASSERT_TRUE(frames) << error;
  Frame frame;
  ASSERT_EQ(frames->Next(&frame, &error), FrameSource::Status::kFrame) << error;
  std::optional<Models> models = DescribeModels(s.models, s.recognition, &error);
  ASSERT_TRUE(models) << error;
  RecognizeStage recognize(RecognizeStage::MakeConfig(s, std::move(*models)));
  const std::int64_t now = SteadyNowNs(), hour = 3600 * std::int64_t{1000000000};
  for (const std::int64_t until : {std::int64_t{0}, now + hour, now - hour}) {
    AttendStage attend(s.attention, s.initial_fovea_m);
    TrackStage track(s.tracking);
    Job job;
    job.frame = frame;
    job.frame.arrival_steady_ns = now;
    job.looks_until_ns = until;
    attend.Plan(&job);
    track.PlanRecognition(&job);
    ASSERT_EQ(job.plan.left, 2);
    recognize.Process(&job);
    const bool in_time = until != now - hour;
    EXPECT_EQ(job.looks.size(), in_time ? 2u : 0u) << "until " << until;
    EXPECT_EQ(job.detections.instances.empty(), !in_time) << "until " << until;
  }
}

// Where the limit falls: a frame keeps pace when it leaves the pipeline before the frame
// frames_in_flight after it arrives; a quarter period is left for tracking and publishing.
TEST(Tracker, LooksEndBeforeTheFrameAfterArrives) {
  const std::int64_t ms = 1000000;
  EXPECT_EQ(LooksUntilNs(100 * ms, 0, 1), 100 * ms);  // the period not known yet: no further look
  EXPECT_EQ(LooksUntilNs(100 * ms, 40 * ms, 1), 130 * ms);
  EXPECT_EQ(LooksUntilNs(100 * ms, 40 * ms, 2), 170 * ms);
  ArrivalPeriod period;
  EXPECT_EQ(period.ns(), 0);
  period.Add(1000 * ms, 10);
  EXPECT_EQ(period.ns(), 0);
  // 33 ms apart, one late (40 ms) and one early (26 ms): the median holds 33.
  std::uint64_t seq = 10;
  for (const std::int64_t at : {1033, 1066, 1106, 1132, 1165}) period.Add(at * ms, ++seq);
  EXPECT_EQ(period.ns(), 33 * ms);
  // Then every second frame dropped for a while (66 ms, two frames a gap): still 33.
  for (int i = 1; i <= 10; ++i) {
    seq += 2;
    period.Add((1165 + 66 * i) * ms, seq);
  }
  EXPECT_EQ(period.ns(), 33 * ms);
}

// The preview (on in the demo's config) is made from the frame it describes, at most rate_hz
// a second: at one in 1000 s only the first frame's is due, whatever the machine's speed.
TEST(Tracker, APreviewDescribesItsFrameAndComesAtMostAtItsRate) {
  DaemonSettings settings = DemoSettings();
  ASSERT_TRUE(settings.preview.enabled);
  settings.preview.rate_hz = 1e-3;
  Rig rig(settings);
  ASSERT_TRUE(rig.tracker);
  while (rig.Step()) {
  }
  const auto published = rig.bus->Frames();
  const auto previews = rig.bus->Previews();
  ASSERT_EQ(published.size(), 6u);
  ASSERT_EQ(previews.size(), 1u);
  const Preview& p = previews[0];
  const FrameDetections& first = published[0].frame;
  EXPECT_EQ(p.seq, first.seq);
  EXPECT_EQ(p.fovea_m, first.fovea_m);
  EXPECT_EQ(p.growth_m, first.growth_m);
  ASSERT_EQ(p.instance_centroids_m.size(), first.instances.size());
  for (std::size_t i = 0; i < first.instances.size(); ++i)
    EXPECT_EQ(p.instance_centroids_m[i], first.instances[i].centroid_m);
  // The image is the frame decimated by image_step; the synthetic frames carry their truth.
  const int step = settings.preview.image_step;
  EXPECT_EQ(p.intrinsics.width, 640 / step);
  EXPECT_EQ(p.intrinsics.height, 480 / step);
  EXPECT_EQ(p.rgb.size(), static_cast<std::size_t>(p.intrinsics.width) * p.intrinsics.height * 3);
  EXPECT_TRUE(p.has_truth);
  EXPECT_FALSE(p.points_mm.empty());
  EXPECT_EQ(p.points_mm.size(), 3 * p.levels.size());

  settings.preview.enabled = false;  // off (saccaded's default): none at all
  Rig off(settings);
  ASSERT_TRUE(off.tracker);
  while (off.Step()) {
  }
  EXPECT_EQ(off.bus->Frames().size(), 6u);
  EXPECT_TRUE(off.bus->Previews().empty());
}

TEST(Tracker, SetFoveaMovesTheNextFixationAndResetReturnsToTheInitialFovea) {
  const DaemonSettings settings = DemoSettings();
  Rig rig(settings);
  ASSERT_TRUE(rig.tracker);
  ASSERT_TRUE(rig.Step());
  Command look;
  look.kind = Command::Kind::kSetFovea;
  look.fovea_m = Eigen::Vector3f(0.5f, 0.1f, 1.5f);
  ASSERT_TRUE(rig.bus->Send(look));
  ASSERT_TRUE(rig.Step());
  Command reset;
  reset.kind = Command::Kind::kReset;
  ASSERT_TRUE(rig.bus->Send(reset));
  ASSERT_TRUE(rig.Step());
  const auto published = rig.bus->Frames();
  ASSERT_EQ(published.size(), 3u);
  EXPECT_EQ(published[1].fixation.reason.rfind("command", 0), 0u) << published[1].fixation.reason;
  EXPECT_TRUE(published[1].fixation.fovea_m.isApprox(look.fovea_m));
  EXPECT_EQ(published[1].fixation.mode, AttentionMode::kSearching);
  EXPECT_TRUE(published[2].frame.fovea_m.isApprox(look.fovea_m));  // foveated where asked
  EXPECT_EQ(published[2].fixation.reason.rfind("reset", 0), 0u) << published[2].fixation.reason;
  EXPECT_TRUE(published[2].fixation.fovea_m.isApprox(settings.initial_fovea_m));
  EXPECT_EQ(rig.bus->AcceptedCommands(), 2);
  EXPECT_EQ(rig.bus->RejectedCommands(), 0);
}

TEST(Tracker, ModelSwitchesAndReloadsRunOnTheControlThreadAndABadOneChangesNothing) {
  DaemonSettings settings = DemoSettings();
  Rig rig(settings);
  ASSERT_TRUE(rig.tracker);
  Command missing;
  missing.kind = Command::Kind::kSwitchModel;
  missing.model = "/nonexistent/model.pcd";
  ASSERT_TRUE(rig.bus->Send(missing));  // returns before the model is tried
  rig.tracker->WaitForControl();
  EXPECT_EQ(rig.bus->RejectedCommands(), 1);
  EXPECT_EQ(rig.bus->AcceptedCommands(), 0);

  DaemonSettings bad = settings;
  bad.models = {"/nonexistent/other.pcd"};
  bool bad_ok = true;
  std::string bad_error;
  rig.tracker->Reload(bad, [&](bool ok, const std::string& e) { bad_ok = ok, bad_error = e; });
  rig.tracker->WaitForControl();
  EXPECT_FALSE(bad_ok);
  EXPECT_NE(bad_error.find("/nonexistent/other.pcd"), std::string::npos) << bad_error;

  // The running model still finds the target.
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(rig.Step());
  EXPECT_FALSE(rig.bus->Frames().back().frame.instances.empty());

  // A reload no instance can pass: nothing is found from the next frame on.
  DaemonSettings strict = settings;
  strict.recognition.hough_threshold = 100000;
  strict.recognition.consensus_min_votes = 100000;
  bool strict_ok = false;
  rig.tracker->Reload(strict, [&](bool ok, const std::string&) { strict_ok = ok; });
  rig.tracker->WaitForControl();
  EXPECT_TRUE(strict_ok);
  ASSERT_TRUE(rig.Step());
  EXPECT_TRUE(rig.bus->Frames().back().frame.instances.empty());
}

TEST(Tracker, AFloodOfModelSwitchesDescribesOnlyTheLast) {
  Rig rig(DemoSettings());
  ASSERT_TRUE(rig.tracker);
  Command change;
  change.kind = Command::Kind::kSwitchModel;
  change.model = "synthetic:target";
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(rig.bus->Send(change));
  rig.tracker->WaitForControl();
  // Each switch waiting when a later one came was refused: the first may have begun before the
  // second arrived; the last is loaded. Every command is counted once.
  EXPECT_EQ(rig.bus->AcceptedCommands() + rig.bus->RejectedCommands(), 200);
  EXPECT_GE(rig.bus->AcceptedCommands(), 1);
  EXPECT_LE(rig.bus->AcceptedCommands(), 2);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(rig.Step());
  EXPECT_FALSE(rig.bus->Frames().back().frame.instances.empty());
  // Once the tracker stops, a switch is refused rather than described.
  rig.tracker->Stop();
  ASSERT_TRUE(rig.bus->Send(change));
  rig.tracker->WaitForControl();
  EXPECT_EQ(rig.bus->RejectedCommands() + rig.bus->AcceptedCommands(), 201);
  EXPECT_LE(rig.bus->AcceptedCommands(), 2);
}

// Two models searched as one library (core/library.h): every frame names both, the target is
// found by its own model at its true place, and no instance of the other model claims it.
TEST(Tracker, TwoModelsAreSearchedAsOneLibraryAndEachInstanceNamesItsModel) {
  DaemonSettings s = DemoSettings();
  s.models = {"synthetic:target", "synthetic:ball"};
  Rig rig(s);
  ASSERT_TRUE(rig.tracker);
  while (rig.Step()) {
  }
  const auto published = rig.bus->Frames();
  ASSERT_EQ(published.size(), 6u);
  bool target_found = false;
  for (std::size_t i = 0; i < published.size(); ++i) {
    const FrameDetections& frame = published[i].frame;
    ASSERT_EQ(frame.models, (std::vector<std::string>{"synthetic:target", "synthetic:ball"}));
    ASSERT_TRUE(rig.truths[i]);
    const Eigen::Isometry3f& truth = rig.truths[i]->target_pose;
    for (const Detection& d : frame.instances) {
      ASSERT_TRUE(d.model == 0 || d.model == 1);
      // The target's model centroid where the true pose puts it (its models are cut in its frame).
      const Eigen::Vector3f in_model = Eigen::Isometry3f(d.model_to_scene).inverse() * d.centroid_m;
      if (d.model == 0 && (d.centroid_m - truth * in_model).norm() < 0.02f) target_found = true;
      if (d.model == 1) {
        EXPECT_GT((d.centroid_m - truth.translation()).norm(), 0.08f)
            << "frame " << i << ": the ball's model on the target";
      }
    }
  }
  EXPECT_TRUE(target_found);
}

}  // namespace
}  // namespace saccade

namespace saccade {
namespace {

// Every DETECTIONS message carries each track's state, and the states follow each other as
// attention/tracks.h says, on the demo's sequence (the target slides, hides behind a screen for
// frames 45-59 and comes out): found, held, lost within two frames of hiding, searched for,
// re-acquired after it comes out; and the held instances are where the truth is.
TEST(Tracker, EveryMessageCarriesTheTrackStatesInOrderThroughAnOcclusion) {
  DaemonSettings settings = DemoSettings();
  settings.source.spec = "synthetic:" + kSourceDir + "/configs/demo-scenario.yaml?rate=0";
  Rig rig(settings);
  ASSERT_TRUE(rig.tracker);
  std::vector<GroundTruth> truth;
  for (;;) {
    Frame f;
    std::string error;
    if (rig.frames->Next(&f, &error) != FrameSource::Status::kFrame) break;
    truth.push_back(*f.truth);
    rig.tracker->Process(std::move(f));
  }
  const auto published = rig.bus->Frames();
  ASSERT_EQ(published.size(), 120u);
  const auto allowed = [](TrackState from, TrackState to) {
    switch (from) {
      case TrackState::kReacquired:
      case TrackState::kTracking:
        return to == TrackState::kTracking || to == TrackState::kLost ||
               to == TrackState::kReacquired;
      case TrackState::kLost:
        return to == TrackState::kSearching || to == TrackState::kReacquired;
      case TrackState::kSearching:
        return to == TrackState::kSearching || to == TrackState::kReacquired;
      case TrackState::kNone:
        return false;
    }
    return false;
  };
  std::map<int, TrackState> last;
  int first_hidden = -1, lost_at = -1, reappeared = -1, reacquired_at = -1, held_frames = 0;
  for (std::size_t i = 0; i < published.size(); ++i) {
    const bool visible = truth[i].visible_fraction >= 0.2f;
    if (!visible && first_hidden < 0 && i > 0) first_hidden = int(i);
    if (visible && first_hidden >= 0 && reappeared < 0) reappeared = int(i);
    for (const Detection& d : published[i].frame.instances) {
      ASSERT_GE(d.track_id, 0) << "frame " << i;
      ASSERT_NE(d.track_state, TrackState::kNone) << "frame " << i;
      const auto was = last.find(d.track_id);
      if (was == last.end())
        EXPECT_EQ(d.track_state, TrackState::kReacquired) << "frame " << i << ": a new track";
      else
        EXPECT_TRUE(allowed(was->second, d.track_state))
            << "frame " << i << " track " << d.track_id << ": " << TrackStateName(was->second)
            << " -> " << TrackStateName(d.track_state);
      last[d.track_id] = d.track_state;
      if (d.track_id != 0) continue;
      if (d.track_state == TrackState::kLost && first_hidden >= 0 && lost_at < 0) lost_at = int(i);
      if (d.track_state == TrackState::kReacquired && reappeared >= 0 && reacquired_at < 0)
        reacquired_at = int(i);
      if (visible &&
          (d.track_state == TrackState::kTracking || d.track_state == TrackState::kReacquired)) {
        const float e =
            (d.centroid_m -
             truth[i].target_pose * (Eigen::Isometry3f(d.model_to_scene).inverse() * d.centroid_m))
                .norm();
        EXPECT_LT(e, 0.01f) << "frame " << i;
        ++held_frames;
      }
    }
  }
  ASSERT_GT(first_hidden, 0);
  ASSERT_GT(reappeared, first_hidden);
  EXPECT_GE(lost_at, first_hidden);
  EXPECT_LE(lost_at, first_hidden + 2);
  EXPECT_GE(reacquired_at, reappeared);
  EXPECT_LE(reacquired_at, reappeared + 3);
  EXPECT_GT(held_frames, 90);  // of the 105 frames the target is visible
}

}  // namespace
}  // namespace saccade
