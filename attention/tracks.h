// The tracks of issue 16: once recognition finds an object, each new frame refines its last
// pose (seeded by the constant-velocity prediction) with core/tracking.h's TrackPose instead of
// recognizing it again. A track is TRACKING while the frame supports it, LOST on the first
// frame that does not, SEARCHING after that (attention grows the fovea, recognition runs), and
// RE-ACQUIRED on the frame recognition finds it again (or, while it is searched for, the frame
// supports it again where it was lost). Recognition also re-checks every track
// every few frames and whenever its score drops, so a track that slid onto a neighbour is put
// back. Several objects at once, each with a stable id. Pure: frames and recognition's
// instances in, the frame's instances with their track ids and states out. Not thread-safe.
#pragma once

#include "core/camera.h"
#include "core/schema.h"
#include "core/tracking.h"
#include "core/types.h"

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

struct TrackingOptions {
  /// Off: recognition runs on every frame and its instances are published as they are
  /// (track_state NONE), the behaviour before tracking.
  bool enabled = true;
  /// Recognition re-checks a tracked object after this many frames without it (1: every frame,
  /// recognition's cost each frame; tracking then only smooths and names).
  int recheck_every = 10;
  /// A track whose fitness falls below this (but not below TrackOptions::min_fitness) is
  /// re-checked on the next frame.
  float recheck_below_fitness = 0.8f;
  /// A track not confirmed by this many re-checks in a row (recognition ran at its place and
  /// found no instance of its model near it) is LOST: a track on a wrong object does not hold.
  /// A track just (re-)acquired is re-checked on the next frame and one miss there loses it:
  /// a false instance of one frame does not become a track.
  int unconfirmed_rechecks = 3;
  /// A recognized instance whose centroid is this near a track's (prediction) is that track.
  float same_track_m = 0.05f;
  /// A second track of a model already tracked starts only from an instance this confident
  /// (of recognition's instances at >= 0.9, 97% were true on the cross-capture benchmark,
  /// docs/RESULTS.md): one object per model is the common case, and a look-alike the usual
  /// false instance.
  float min_extra_track_confidence = 0.9f;
  /// The first track of a model starts only from an instance this confident, unless attention
  /// chose the instance itself (TrackFrame::attended: the most confident of a whole search):
  /// a look-alike seen first is not locked onto (docs/RESULTS.md, issue 34).
  float min_track_confidence = 0.9f;
  /// A lost track is re-acquired by an instance farther than this from its last held pose only
  /// at min_extra_track_confidence (and a less confident instance this near a held track that
  /// recognition did not confirm is its object at a worse pose): while the object hides, a
  /// look-alike elsewhere in the view is the usual false instance, and recognition finds it
  /// again at every search. On make bench-track, 0.05 and 0.1 hold the same frames and 0.05
  /// the fewer wrong ones (0 and 2 of 1,403); 0.2 and more re-acquire test31's look-alike, 22.6
  /// cm from the can (docs/BENCHMARKS.md).
  float reacquire_radius_m = 0.05f;
  /// A re-check describes at most this many scene keypoints, the nearest the fovea (on the
  /// track); 0: recognition.max_scene_keypoints, as any search. 0, 300 and 600 held the same
  /// frames on make bench-track's 15 sequences; 300 cut a re-check from ~10 to ~7.5 ms (p50).
  int recheck_max_keypoints = 300;
  int max_tracks = 4;  // tracks kept at once; a new object past this is not tracked
  /// A track the frame stopped supporting (not one recognition stopped confirming) is tried
  /// again where it was lost on each of this many frames after (TrackSet::Watch): where the
  /// frame supports it there again, with at least 30% of it in the image, it is RE-ACQUIRED
  /// without waiting for recognition, which does not find an object that comes back a fifth
  /// in view at the image's edge. 0: only recognition re-acquires; 300 (forget_after_frames):
  /// as long as it is searched for.
  int watch_lost_frames = 300;
  /// A track searched for this many frames is forgotten (its id is not reused).
  int forget_after_frames = 300;
  TrackOptions refine;  // TrackPose's options: the section's other keys

  bool IsValid(std::string* error) const;
  bool operator==(const TrackingOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const TrackingOptions& o) const { return !(*this == o); }
  /// The keys of the `tracking` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("enabled", &enabled);
    a->Visit("recheck_every", &recheck_every);
    a->Visit("recheck_below_fitness", &recheck_below_fitness);
    a->Visit("unconfirmed_rechecks", &unconfirmed_rechecks);
    a->Visit("same_track_m", &same_track_m);
    a->Visit("min_extra_track_confidence", &min_extra_track_confidence);
    a->Visit("min_track_confidence", &min_track_confidence);
    a->Visit("reacquire_radius_m", &reacquire_radius_m);
    a->Visit("recheck_max_keypoints", &recheck_max_keypoints);
    a->Visit("max_tracks", &max_tracks);
    a->Visit("watch_lost_frames", &watch_lost_frames);
    a->Visit("forget_after_frames", &forget_after_frames);
    refine.Serialize(a);
  }
};

/// A model as tracks see it: the points and normals TrackPose aligns, and its centroid (model
/// frame) that instances report.
struct TrackModel {
  const VerificationModel* points = nullptr;  // outlives the call it is passed to
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
};

/// One frame as tracks see it.
struct TrackFrame {
  std::int64_t seq = 0;
  double time_s = 0;
  const Cloud* cloud = nullptr;  // organized, intrinsics' size, or tracks cannot be refined on it
  CameraIntrinsics intrinsics;
  bool recognized = false;  // recognition ran on this frame (its instances may still be none)
  /// Where recognition searched (a re-check confirms only the tracks inside): the fovea's centre
  /// and the half-size of its largest box; a negative half-size means the whole frame.
  Eigen::Vector3f searched_centre_m = Eigen::Vector3f::Zero();
  float searched_half_m = -1;
  /// Recognition swept the frame for models no track holds (SweepPhase): what it found takes
  /// part as always, but a held track it did not find is not counted as missed.
  bool sweep = false;
  /// The models recognition ran for (ModelsToRecognize); empty: all. A held track of a model
  /// it did not run for is neither confirmed nor missed.
  std::vector<bool> recognized_models;
  /// Attention foveated this frame on an instance it chose to follow without a track (the best
  /// of a search that found none at min_track_confidence): a track may start from it below
  /// that bar.
  bool attended = false;
};

class TrackSet {
 public:
  explicit TrackSet(const TrackingOptions& options) : options_(options) {}

  /// Whether the next frame needs recognition: a re-check is due, a score dropped, no track is
  /// held (attention searches), or a model no track holds is due a sweep (always, with
  /// tracking off).
  bool NeedsRecognition() const;
  /// While tracks are held and a model has none (never found, or lost), recognition sweeps the
  /// whole frame for it every recheck_every frames, within the keypoint budget: the window to
  /// describe (SceneQuery::search_phase: even the nearest the fovea, odd ones walking out), or
  /// -1 when the next frame's recognition, if any, is a re-check at the fovea.
  int SweepPhase() const;
  /// Where the next frame's re-check looks: the centroid of the held track most overdue
  /// (camera frame, at its last pose). A re-check recognizes at the track, whatever attention
  /// follows; one track a frame, the others stay due. nullopt when no re-check is due.
  std::optional<Eigen::Vector3f> RecheckAt() const;
  /// Which models the next frame's recognition needs, by model index: the re-checked track's,
  /// those a sweep looks for, every model while nothing is held; empty: all of them. A re-check
  /// then costs one model's recognition, not every model's.
  std::vector<bool> ModelsToRecognize() const;
  /// Digests one frame: refines every held track on it, then takes recognition's instances
  /// (when it ran; `models` indexed by Detection::model). Returns the frame's instances: every
  /// track's, with its id, state and confidence (TRACKING: the track score; LOST and SEARCHING:
  /// 0 at the last pose), and recognized instances no track took (state RE-ACQUIRED with a new
  /// id; NONE with id -1 past max_tracks or min_extra_track_confidence). Appends what changed to
  /// `events` (may be null),
  /// "; "-separated, for the fixation log: "track 0 lost (fitness 0.41 coverage 0.12)".
  std::vector<Detection> Update(const TrackFrame& frame, const std::vector<TrackModel>& models,
                                const std::vector<Detection>& recognized, std::string* events);
  /// Forgets every track (a model switch, a RESET); ids go on from where they were.
  void Clear() {
    tracks_.clear();
    unheld_frames_.clear();
    sweeps_ = 0;
  }
  void SetOptions(const TrackingOptions& options) { options_ = options; }
  const TrackingOptions& options() const { return options_; }
  std::size_t size() const { return tracks_.size(); }

 private:
  struct Track {
    int id = 0;
    int model = 0;
    TrackState state = TrackState::kReacquired;
    Eigen::Matrix4f pose = Eigen::Matrix4f::Identity();  // X_CM at time_s
    double time_s = 0;
    /// The last frame-to-frame motion, left-multiplied (X_CM(t) = motion * X_CM(t - dt)), and
    /// its dt; identity until the track has two poses in a row (or, from two recent sightings by
    /// recognition, the translation between them: Matching::MoveBetweenSightings).
    Eigen::Matrix4f motion = Eigen::Matrix4f::Identity();
    double motion_dt_s = 0;
    float fitness = 0, coverage = 0;
    int frames_since_check = 0;  // frames since recognition last looked at it
    int unconfirmed = 0;         // re-checks in a row that did not find it
    std::int64_t lost_seq = -1;  // the frame it was lost on, -1 while held
    bool watched = false;        // lost by the frame, not by re-checks: tried at its last pose
    /// The last held pose with at least min_in_image_to_turn of it in the image: where an
    /// object that left at the edge is seen again when it comes back the way it went
    /// (identity: none yet).
    Eigen::Matrix4f inward_pose = Eigen::Matrix4f::Identity();
    /// Re-acquired where it was lost and not confirmed by recognition since: its turn is held
    /// until it is wholly in the image (its motion is not known yet: a turn would absorb it).
    bool rewatched = false;
    Detection found;  // recognition's instance when it was last (re-)acquired or retaken
    double found_s = std::numeric_limits<double>::quiet_NaN();  // ...and when (NaN: never)
    /// Found on the last recognized frame: this frame's sighting that confirms it gives the
    /// track its motion (Matching::Retake); cleared after any other recognized frame.
    bool first_check = false;
    Eigen::Matrix4f PredictedAt(double time_s) const;
  };

  bool Held(const Track& t) const {
    return t.state == TrackState::kTracking || t.state == TrackState::kReacquired;
  }
  void Refine(const TrackFrame& frame, const std::vector<TrackModel>& models, Track* t,
              std::string* events);
  /// RE-ACQUIRED, tentative (re-checked on the next frame, where one miss loses it), no motion
  /// known; `watched_back`: by Watch, not by recognition (Track::rewatched).
  void Tentative(Track* t, bool watched_back) const;
  /// A lost track within watch_lost_frames, refined (its turn held) from its last held pose,
  /// else from its inward_pose: RE-ACQUIRED where that holds with kMinInImageToWatch of it in
  /// the image.
  void Watch(const TrackFrame& frame, const std::vector<TrackModel>& models, Track* t,
             std::string* events);
  Detection Publish(const Track& t, const std::vector<TrackModel>& models) const;
  /// Lost last frame: searching now; searched for forget_after_frames: forgotten.
  void ForgetLongSearches(std::int64_t seq, std::string* events);
  /// Per model, the frames since a track held it or a sweep looked for it.
  void CountUnheldFrames(const std::vector<TrackModel>& models, bool sweep);
  class Matching;  // a frame's recognized instances matched to the tracks (tracks.cc)

  bool ModelHeld(int model) const;
  bool Due(const Track& t) const;  // held, and its re-check is due
  bool RecheckDue() const;         // some track's is
  const Track* MostOverdue() const;
  bool AnyHeld() const;

  TrackingOptions options_;
  std::vector<Track> tracks_;  // oldest first
  int next_id_ = 0;
  std::vector<Eigen::Vector3f> centroids_;  // each model's centroid, its frame (last Update's)
  std::vector<int> unheld_frames_;  // per model no track holds: frames since it was swept for
  int sweeps_ = 0;                  // sweeps so far (their windows walk outward)
};

}  // namespace saccade
