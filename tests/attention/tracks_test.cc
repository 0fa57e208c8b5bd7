// The tracks on the synthetic Kinect's demo case: a found object is held by tracking alone
// until its re-check, is LOST on the first frame that no longer shows it and SEARCHING after,
// keeps its id when recognition finds it again, and a track recognition does not confirm (or
// finds elsewhere) does not hold.
#include "attention/tracks.h"

#include "core/recognition.h"
#include "support/demo_case.h"

#include <gtest/gtest.h>

namespace saccade {
namespace {

struct Demo : testing::DescribedDemo {
  Demo() {
    // With the object's pixels emptied out (as when it left the view).
    empty = demo.scene.cloud;
    for (PointT& p : empty) {
      const Eigen::Vector3f in_object = demo.truth.inverse() * p.getVector3fMap();
      if (in_object.allFinite() && in_object.norm() < 0.2f)
        p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
    }
  }
  std::vector<TrackModel> Models() const {
    return {TrackModel{&model->verification(), model->centroid()}};
  }
  /// Recognition's instance at `pose` (the truth unless said).
  Detection Found(const Eigen::Matrix4f& pose) const {
    Detection d;
    d.model = 0;
    d.model_to_scene = pose;
    d.centroid_m = Eigen::Affine3f(pose) * model->centroid();
    d.votes = 12;
    d.fitness = 0.9f;
    d.coverage = 0.5f;
    d.confidence = 0.95f;
    return d;
  }
  Detection Found() const { return Found(demo.truth.matrix()); }
  TrackFrame Frame(std::int64_t seq, const Cloud& cloud, bool recognized) const {
    TrackFrame f;
    f.seq = seq;
    f.time_s = seq / 30.0;
    f.cloud = &cloud;
    f.recognized = recognized;
    f.searched_centre_m = demo.truth * model->centroid();
    f.searched_half_m = 0.25f;
    return f;
  }
  /// Found on frame 0, confirmed on frame 1.
  void FindAndConfirm(TrackSet* tracks) const {
    tracks->Update(Frame(0, demo.scene.cloud, true), Models(), {Found()}, nullptr);
    tracks->Update(Frame(1, demo.scene.cloud, true), Models(), {Found()}, nullptr);
  }
  /// ...then lost on frame 2 (the object's pixels emptied).
  void FindThenLose(TrackSet* tracks) const {
    FindAndConfirm(tracks);
    tracks->Update(Frame(2, empty, false), Models(), {}, nullptr);
  }
  Cloud empty;
};

const Demo& TheDemo() {
  static const Demo d;
  return d;
}

// Acquisition on confidence (issue 34): an instance below tracking.min_track_confidence starts
// no track and is published as recognition found it, unless attention chose it (the best of a
// search that found nothing more confident).
TEST(TrackSet, AFirstTrackStartsOnlyFromAConfidentOrAttendedInstance) {
  const Demo& d = TheDemo();
  Detection weak = d.Found();
  weak.confidence = 0.7f;
  TrackSet tracks(TrackingOptions{});
  std::string events;
  std::vector<Detection> out =
      tracks.Update(d.Frame(0, d.demo.scene.cloud, true), d.Models(), {weak}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kNone);
  EXPECT_EQ(out[0].track_id, -1);
  EXPECT_EQ(tracks.size(), 0u);
  EXPECT_EQ(events, "");
  TrackFrame attended = d.Frame(1, d.demo.scene.cloud, true);
  attended.attended = true;
  out = tracks.Update(attended, d.Models(), {weak}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
  EXPECT_EQ(events, "track 0 found (confidence 0.70, the best of a search)");
  TrackingOptions bad;
  bad.min_track_confidence = 1.5f;
  std::string error;
  EXPECT_FALSE(bad.IsValid(&error));
  EXPECT_NE(error.find("min_track_confidence"), std::string::npos);
}

TEST(TrackSet, AFoundObjectIsHeldByTrackingAloneUntilItsRecheck) {
  const Demo& d = TheDemo();
  TrackingOptions o;
  o.recheck_every = 5;
  TrackSet tracks(o);
  EXPECT_TRUE(tracks.NeedsRecognition());  // nothing to track yet
  std::string events;
  std::vector<Detection> out =
      tracks.Update(d.Frame(0, d.demo.scene.cloud, true), d.Models(), {d.Found()}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
  EXPECT_EQ(out[0].track_id, 0);
  EXPECT_FLOAT_EQ(out[0].confidence, 0.95f);  // recognition's, for what it found
  EXPECT_EQ(events, "track 0 found (confidence 0.95)");
  // Tentative: the next frame re-checks it, and recognition confirms it.
  EXPECT_TRUE(tracks.NeedsRecognition());
  out = tracks.Update(d.Frame(1, d.demo.scene.cloud, true), d.Models(), {d.Found()}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kTracking);
  int tracked_alone = 0;
  for (std::int64_t seq = 2; !tracks.NeedsRecognition(); ++seq) {
    events.clear();
    out = tracks.Update(d.Frame(seq, d.demo.scene.cloud, false), d.Models(), {}, &events);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].track_state, TrackState::kTracking) << "frame " << seq;
    EXPECT_EQ(out[0].track_id, 0);
    EXPECT_GT(out[0].confidence, 0.5f);
    const PoseError e =
        ComparePoses(out[0].model_to_scene, d.demo.truth.matrix(), d.model->centroid());
    EXPECT_LT(e.translation_m, 0.003) << "frame " << seq;
    EXPECT_TRUE(events.empty()) << events;
    ++tracked_alone;
  }
  // Frames 2-5 by tracking alone; frame 6 is the re-check.
  EXPECT_EQ(tracked_alone, 4);
}

// A source whose clock jumps (a replugged camera restarts its clock, a recording loops, a
// clock steps by an hour): the motion prediction is bounded (at most three steps of the last
// motion ahead, none backwards), so a held object stays held where it is, its pose finite.
// Each jump comes right after the object moved 1 cm in one frame interval (0.3 m/s), with
// tracks of its own: unbounded, an hour's jump would predict it a kilometre away.
TEST(TrackSet, TimestampsThatJumpBackForwardOrStandStillKeepTheTrackWhereTheObjectIs) {
  const Demo& d = TheDemo();
  const Eigen::Vector3f step(0.01f, 0.0f, 0.0f);
  Cloud before = d.demo.scene.cloud;  // the whole scene 1 cm back: the object's first place
  for (PointT& p : before) p.getVector3fMap() -= step;
  const Eigen::Matrix4f first =
      Eigen::Affine3f(Eigen::Translation3f(-step) * d.demo.truth).matrix();
  const double times[] = {-100.0, 1.0 / 30, 0.5, 3600.0, 1e9};  // frame 1 was at 1/30 s
  for (double t : times) {
    TrackSet tracks(TrackingOptions{});
    tracks.Update(d.Frame(0, before, true), d.Models(), {d.Found(first)}, nullptr);
    tracks.Update(d.Frame(1, d.demo.scene.cloud, true), d.Models(), {d.Found()}, nullptr);
    TrackFrame f = d.Frame(2, d.demo.scene.cloud, false);
    f.time_s = t;
    const std::vector<Detection> out = tracks.Update(f, d.Models(), {}, nullptr);
    ASSERT_EQ(out.size(), 1u) << "time " << t;
    EXPECT_TRUE(out[0].model_to_scene.allFinite()) << "time " << t;
    EXPECT_EQ(out[0].track_state, TrackState::kTracking) << "time " << t;
    const PoseError e =
        ComparePoses(out[0].model_to_scene, d.demo.truth.matrix(), d.model->centroid());
    EXPECT_LT(e.translation_m, 0.003) << "time " << t;
  }
}

TrackingOptions RecognitionAloneReacquires() {
  TrackingOptions o;
  o.watch_lost_frames = 0;  // the frame's own support re-acquires too: below
  return o;
}

TEST(TrackSet, ATrackThatLosesItsObjectIsLostOnThatFrameThenSearchingAndKeepsItsId) {
  const Demo& d = TheDemo();
  TrackSet tracks(RecognitionAloneReacquires());
  tracks.Update(d.Frame(0, d.demo.scene.cloud, true), d.Models(), {d.Found()}, nullptr);
  tracks.Update(d.Frame(1, d.demo.scene.cloud, true), d.Models(), {d.Found()}, nullptr);
  std::string events;
  std::vector<Detection> out = tracks.Update(d.Frame(2, d.empty, false), d.Models(), {}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kLost);
  EXPECT_EQ(out[0].confidence, 0.0f);
  EXPECT_EQ(events.rfind("track 0 lost (fitness", 0), 0u) << events;
  EXPECT_TRUE(tracks.NeedsRecognition());
  out = tracks.Update(d.Frame(3, d.empty, true), d.Models(), {}, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kSearching);
  // Back in view and found again: the same id, re-acquired.
  events.clear();
  out = tracks.Update(d.Frame(4, d.demo.scene.cloud, true), d.Models(), {d.Found()}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
  EXPECT_EQ(out[0].track_id, 0);
  EXPECT_EQ(events, "track 0 re-acquired by recognition after 2 frames");
  out = tracks.Update(d.Frame(5, d.demo.scene.cloud, false), d.Models(), {}, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kTracking);
  EXPECT_LT(
      ComparePoses(out[0].model_to_scene, d.demo.truth.matrix(), d.model->centroid()).translation_m,
      0.003);
}

TEST(TrackSet, ALostTrackIsNotReacquiredByALookAlikeFarFromWhereItWasLost) {
  const Demo& d = TheDemo();
  TrackSet tracks(RecognitionAloneReacquires());
  d.FindThenLose(&tracks);
  // While it hides, recognition finds a look-alike 30 cm away, as confident as a true instance
  // usually is but below min_extra_track_confidence: published untracked, the track searches on.
  Eigen::Matrix4f there = d.demo.truth.matrix();
  there(0, 3) += 0.3f;
  Detection look_alike = d.Found(there);
  look_alike.confidence = 0.84f;
  std::string events;
  std::vector<Detection> out =
      tracks.Update(d.Frame(3, d.empty, true), d.Models(), {look_alike}, &events);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].track_state, TrackState::kSearching);
  EXPECT_EQ(out[1].track_state, TrackState::kNone);
  EXPECT_FALSE(Actionable(out[1].track_state, /*tracking=*/true));  // attention does not follow
  EXPECT_TRUE(events.empty()) << events;
  // The object back where it was lost, found at a lower confidence still: re-acquired.
  Detection back = d.Found();
  back.confidence = 0.6f;
  out =
      tracks.Update(d.Frame(4, d.demo.scene.cloud, true), d.Models(), {look_alike, back}, &events);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].track_id, 0);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
  EXPECT_TRUE(out[0].centroid_m.isApprox(back.centroid_m, 1e-3f));
  EXPECT_EQ(out[1].track_state, TrackState::kNone);
  // Far away but as confident as a second track must be: that moves it.
  TrackSet other(RecognitionAloneReacquires());
  d.FindThenLose(&other);
  out = other.Update(d.Frame(3, d.empty, true), d.Models(), {d.Found(there)}, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
}

// tracking.watch_lost_frames: a track the frame stopped supporting is tried at its last pose
// on the frames after; where the object is back there, it is re-acquired without recognition,
// tentative as any re-acquisition (the next frame re-checks it, and one miss loses it, for
// good: a track recognition did not confirm is not watched). Past the watch, only
// recognition re-acquires.
TEST(TrackSet, ALostTrackIsReacquiredWhereItWasLostWhenTheFrameShowsItThereAgain) {
  const Demo& d = TheDemo();
  TrackingOptions o;
  o.watch_lost_frames = 2;
  TrackSet tracks(o);
  d.FindThenLose(&tracks);
  std::string events;
  std::vector<Detection> out = tracks.Update(d.Frame(3, d.empty, false), d.Models(), {}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kSearching);
  EXPECT_TRUE(events.empty()) << events;
  out = tracks.Update(d.Frame(4, d.demo.scene.cloud, false), d.Models(), {}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
  EXPECT_EQ(out[0].track_id, 0);
  EXPECT_EQ(events.rfind("track 0 re-acquired where it was lost after 2 frames (fitness", 0), 0u)
      << events;
  EXPECT_GT(out[0].confidence, 0.5f);
  EXPECT_LT(
      ComparePoses(out[0].model_to_scene, d.demo.truth.matrix(), d.model->centroid()).translation_m,
      0.003);
  // Re-checked on the next frame: recognition does not find it there, and it is lost again,
  // not to be watched for (the object is back, but the track is not taken back).
  EXPECT_TRUE(tracks.NeedsRecognition());
  ASSERT_TRUE(tracks.RecheckAt());
  out = tracks.Update(d.Frame(5, d.demo.scene.cloud, true), d.Models(), {}, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kLost);
  out = tracks.Update(d.Frame(6, d.demo.scene.cloud, false), d.Models(), {}, nullptr);
  EXPECT_EQ(out[0].track_state, TrackState::kSearching);
  // Taken back on a frame recognition also ran on and found nothing: recognition had its
  // chance first; the track is re-acquired and its re-check is the next frame's.
  TrackSet searched(o);
  d.FindThenLose(&searched);
  searched.Update(d.Frame(3, d.empty, true), d.Models(), {}, nullptr);
  out = searched.Update(d.Frame(4, d.demo.scene.cloud, true), d.Models(), {}, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
  EXPECT_TRUE(searched.RecheckAt());
  // Past the watch (lost on frame 2, back on frame 5, 3 frames on): recognition's alone.
  TrackSet late(o);
  d.FindThenLose(&late);
  late.Update(d.Frame(3, d.empty, false), d.Models(), {}, nullptr);
  late.Update(d.Frame(4, d.empty, false), d.Models(), {}, nullptr);
  out = late.Update(d.Frame(5, d.demo.scene.cloud, false), d.Models(), {}, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kSearching);
}

TEST(TrackSet, ARecheckThatFindsTheObjectElsewherePutsTheTrackBack) {
  const Demo& d = TheDemo();
  TrackSet tracks(TrackingOptions{});
  tracks.Update(d.Frame(0, d.demo.scene.cloud, true), d.Models(), {d.Found()}, nullptr);
  // The re-check finds the model 40 cm away and nothing where the track is: recognition, not
  // the track, is trusted (the track may have slid onto a look-alike).
  Eigen::Matrix4f there = d.demo.truth.matrix();
  there(0, 3) += 0.4f;
  std::string events;
  const std::vector<Detection> out =
      tracks.Update(d.Frame(1, d.demo.scene.cloud, true), d.Models(), {d.Found(there)}, &events);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_id, 0);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
  EXPECT_LT(ComparePoses(out[0].model_to_scene, there, d.model->centroid()).translation_m, 1e-4);
  EXPECT_EQ(events, "track 0 put back by recognition (40.0 cm off)");
}

TEST(TrackSet, ATrackRecognitionDoesNotConfirmIsLostAfterTheConfiguredRechecks) {
  const Demo& d = TheDemo();
  TrackingOptions o;
  o.unconfirmed_rechecks = 2;
  TrackSet tracks(o);
  d.FindAndConfirm(&tracks);
  std::vector<Detection> out =
      tracks.Update(d.Frame(2, d.demo.scene.cloud, true), d.Models(), {}, nullptr);
  EXPECT_EQ(out.at(0).track_state, TrackState::kTracking);  // one miss: recognition misses
  std::string events;
  out = tracks.Update(d.Frame(3, d.demo.scene.cloud, true), d.Models(), {}, &events);
  EXPECT_EQ(out.at(0).track_state, TrackState::kLost);
  EXPECT_EQ(events, "track 0 lost (not confirmed by 2 re-checks)");
}

// An object the image's edge cuts off: recognition cannot confirm what it sees only part of,
// so re-checks that miss it there do not lose the track tracking holds.
TEST(TrackSet, ARecheckDoesNotCountAgainstAnObjectTheEdgeCutsOff) {
  const Demo& d = TheDemo();
  TrackingOptions o;
  o.unconfirmed_rechecks = 2;
  TrackSet tracks(o);
  d.FindAndConfirm(&tracks);
  // The same frame with its columns right of the object's centre cut away.
  const CameraIntrinsics k;
  const int edge = int(k.Project(d.demo.truth * d.model->centroid()).x()) + 10;
  Cloud cut(edge, d.demo.scene.cloud.height);
  for (int v = 0; v < int(cut.height); ++v)
    for (int u = 0; u < edge; ++u) cut.at(u, v) = d.demo.scene.cloud.at(u, v);
  std::vector<Detection> out;
  for (std::int64_t seq = 2; seq <= 4; ++seq) {
    TrackFrame f = d.Frame(seq, cut, true);
    f.intrinsics.width = edge;
    std::string events;
    out = tracks.Update(f, d.Models(), {}, &events);
    EXPECT_EQ(events.find("not confirmed"), std::string::npos) << events;
  }
  EXPECT_EQ(out.at(0).track_state, TrackState::kTracking);
}

TEST(TrackSet, AJustFoundTrackThatTheNextRecheckDoesNotFindIsLost) {
  const Demo& d = TheDemo();
  TrackSet tracks(TrackingOptions{});
  tracks.Update(d.Frame(0, d.demo.scene.cloud, true), d.Models(), {d.Found()}, nullptr);
  EXPECT_TRUE(tracks.NeedsRecognition());
  std::string events;
  const std::vector<Detection> out =
      tracks.Update(d.Frame(1, d.demo.scene.cloud, true), d.Models(), {}, &events);
  EXPECT_EQ(out.at(0).track_state, TrackState::kLost);
  EXPECT_EQ(events, "track 0 lost (not confirmed by 3 re-checks)");
}

TEST(TrackSet, ASecondObjectGetsItsOwnIdAndMaxTracksAndConfidenceBoundThem) {
  const Demo& d = TheDemo();
  TrackingOptions o;
  o.max_tracks = 2;
  TrackSet tracks(o);
  Eigen::Matrix4f a = d.demo.truth.matrix(), b = a, c = a, e = a;
  b(0, 3) += 0.3f;
  c(0, 3) -= 0.3f;
  e(1, 3) -= 0.3f;
  Detection unsure = d.Found(e);
  unsure.confidence = 0.7f;  // below min_extra_track_confidence
  const std::vector<Detection> out =
      tracks.Update(d.Frame(0, d.demo.scene.cloud, true), d.Models(),
                    {d.Found(a), d.Found(b), d.Found(c), unsure}, nullptr);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].track_id, 0);
  EXPECT_EQ(out[1].track_id, 1);
  for (std::size_t k : {2u, 3u}) {  // past max_tracks, or unsure: published, not tracked
    EXPECT_EQ(out[k].track_id, -1);
    EXPECT_EQ(out[k].track_state, TrackState::kNone);
  }
  EXPECT_TRUE(out[3].centroid_m.isApprox(unsure.centroid_m));
  EXPECT_EQ(tracks.size(), 2u);
}

TEST(TrackSet, AModelNoTrackHoldsIsSweptForAndAnotherModelsPlaceIsNotItsTrack) {
  const Demo& d = TheDemo();
  TrackingOptions o;
  o.recheck_every = 4;
  TrackSet tracks(o);
  // Two models (the same cloud twice): recognition finds model 0, and model 1 at its place.
  const std::vector<TrackModel> models = {d.Models()[0], d.Models()[0]};
  Detection other = d.Found();
  other.model = 1;
  other.confidence = 0.8f;
  std::vector<Detection> out =
      tracks.Update(d.Frame(0, d.demo.scene.cloud, true), models, {d.Found(), other}, nullptr);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].track_state, TrackState::kReacquired);
  EXPECT_EQ(out[1].track_state, TrackState::kNone);  // model 0's track stands there
  EXPECT_EQ(out[1].model, 1);
  tracks.Update(d.Frame(1, d.demo.scene.cloud, true), models, {d.Found()}, nullptr);
  // Model 0 held, model 1 nowhere: a sweep every recheck_every frames, its windows in turn.
  std::vector<int> sweeps;
  for (std::int64_t seq = 2; seq < 12; ++seq) {
    const bool recognize = tracks.NeedsRecognition();
    const int phase = tracks.SweepPhase();
    EXPECT_EQ(recognize, phase >= 0 || seq % 4 == 1) << "frame " << seq;
    if (phase >= 0) sweeps.push_back(int(seq));
    TrackFrame f = d.Frame(seq, d.demo.scene.cloud, recognize);
    f.sweep = phase >= 0;
    if (recognize) {  // a re-check runs model 0's recognition alone, a sweep model 1's
      f.recognized_models = tracks.ModelsToRecognize();
      EXPECT_EQ(f.recognized_models, (std::vector<bool>{!f.sweep, f.sweep})) << "frame " << seq;
    }
    // A sweep's window holds nothing: model 0's track is not missed for it; its re-checks
    // find it.
    out = tracks.Update(
        f, models,
        recognize && !f.sweep ? std::vector<Detection>{d.Found()} : std::vector<Detection>{},
        nullptr);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].track_state, TrackState::kTracking) << "frame " << seq;
  }
  EXPECT_FALSE(sweeps.empty());
  for (std::size_t k = 1; k < sweeps.size(); ++k) EXPECT_GE(sweeps[k] - sweeps[k - 1], 4);
  // A re-check looks at the track, whatever attention follows.
  tracks.Update(d.Frame(12, d.demo.scene.cloud, false), models, {}, nullptr);
  while (!tracks.RecheckAt())
    tracks.Update(d.Frame(13, d.demo.scene.cloud, false), models, {}, nullptr);
  EXPECT_LT((*tracks.RecheckAt() - d.demo.truth * d.model->centroid()).norm(), 0.01f);
  // What a sweep finds of model 1 away from model 0's track becomes its track.
  while (tracks.SweepPhase() < 0) {
    TrackFrame f = d.Frame(14, d.demo.scene.cloud, tracks.NeedsRecognition());
    tracks.Update(f, models,
                  f.recognized ? std::vector<Detection>{d.Found()} : std::vector<Detection>{},
                  nullptr);
  }
  Eigen::Matrix4f there = d.demo.truth.matrix();
  there(0, 3) += 0.3f;
  Detection found = d.Found(there);
  found.model = 1;
  TrackFrame f = d.Frame(15, d.demo.scene.cloud, true);
  f.sweep = true;
  out = tracks.Update(f, models, {found}, nullptr);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].model, 1);
  EXPECT_EQ(out[1].track_state, TrackState::kReacquired);
  EXPECT_NE(out[1].track_id, out[0].track_id);
}

TEST(TrackSet, WithTrackingOffRecognitionsInstancesPassThrough) {
  const Demo& d = TheDemo();
  TrackingOptions o;
  o.enabled = false;
  TrackSet tracks(o);
  const std::vector<Detection> out =
      tracks.Update(d.Frame(0, d.demo.scene.cloud, true), d.Models(), {d.Found()}, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].track_state, TrackState::kNone);
  EXPECT_EQ(out[0].track_id, -1);
  EXPECT_TRUE(tracks.NeedsRecognition());
}

TEST(TrackingOptions, InvalidValuesNameTheField) {
  std::string error;
  TrackingOptions o;
  o.recheck_every = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("recheck_every"), std::string::npos) << error;
  o = TrackingOptions{};
  o.refine.min_coverage = 3;  // TrackPose's keys are the section's too
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("min_coverage"), std::string::npos) << error;
}

}  // namespace
}  // namespace saccade
