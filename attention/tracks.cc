#include "attention/tracks.h"

#include "core/fail.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numeric>

namespace saccade {
namespace {

// Two sightings by recognition give a track its motion when at most this far apart in time
// (a search's eight candidate visits and a re-check, at 30 Hz)...
constexpr double kSightingsApartMaxS = 0.5;
// ...and the object moved between them no faster than this (the benchmark's fastest is 1 m/s)
constexpr float kMaxSpeedMps = 2.0f;
// ...and farther than this: recognition's poses of a still object differ by up to about its
// ICP's reach (verification's 8 mm inlier distance), and a slower move is one tracking follows
// from a still start (1.5 cm a frame is 0.45 m/s at 30 Hz).
constexpr float kMinSightedMoveM = 0.015f;

// A lost track is re-acquired at its last pose only where this share of its model (of the
// points facing the camera) falls inside the image: a sliver at the edge fits anything.
constexpr float kMinInImageToWatch = 0.3f;
// ...and a held track is lost once less than this share of it is inside the image: the object
// has left the view, whatever the sliver left at the edge still fits. 0.1, 0.15 and 0.2 tried
// on make bench-track: 0.1 held two-objects' can 4-5 frames after its truth said it was gone
// (under a fifth of its pixels in view), 0.2 lost synthetic-leave-return's target 2 frames
// while its truth still counted it in view, 0.15 one, and holds no track more than 2 frames
// after it is gone.
constexpr float kMinInImageToHold = 0.15f;

Eigen::Vector3f CentroidOf(const Eigen::Matrix4f& X_CM, const Eigen::Vector3f& model_centroid) {
  return Eigen::Affine3f(X_CM) * model_centroid;
}

void Say(std::string* events, const std::string& what) {
  if (!events) return;
  if (!events->empty()) *events += "; ";
  *events += what;
}

std::string Figures(const char* what, int id, float fitness, float coverage) {
  char s[120];
  std::snprintf(s, sizeof s, "track %d %s (fitness %.2f coverage %.2f)", id, what, fitness,
                coverage);
  return s;
}

// A track's score on the frame: the share of its points the frame does not contradict,
// discounted while less than half of what faces the camera is found.
float TrackScore(float fitness, float coverage) {
  return fitness * std::min(1.0f, coverage / 0.5f);
}

bool FrameUsable(const TrackFrame& f) {
  return f.cloud && f.cloud->height > 1 && static_cast<int>(f.cloud->width) == f.intrinsics.width &&
         static_cast<int>(f.cloud->height) == f.intrinsics.height;
}

}  // namespace

bool TrackingOptions::IsValid(std::string* error) const {
  if (recheck_every < 1) return Fail(error, "recheck_every must be >= 1");
  if (!(recheck_below_fitness >= 0 && recheck_below_fitness <= 1))
    return Fail(error, "recheck_below_fitness must be in [0, 1]");
  if (unconfirmed_rechecks < 1) return Fail(error, "unconfirmed_rechecks must be >= 1");
  if (!(same_track_m > 0)) return Fail(error, "same_track_m must be > 0");
  if (!(min_extra_track_confidence >= 0 && min_extra_track_confidence <= 1))
    return Fail(error, "min_extra_track_confidence must be in [0, 1]");
  if (!(min_track_confidence >= 0 && min_track_confidence <= 1))
    return Fail(error, "min_track_confidence must be in [0, 1]");
  if (!(reacquire_radius_m >= same_track_m))
    return Fail(error, "reacquire_radius_m must be >= same_track_m");
  if (recheck_max_keypoints < 0) return Fail(error, "recheck_max_keypoints must be >= 0");
  if (max_tracks < 1) return Fail(error, "max_tracks must be >= 1");
  if (watch_lost_frames < 0) return Fail(error, "watch_lost_frames must be >= 0");
  if (forget_after_frames < 1) return Fail(error, "forget_after_frames must be >= 1");
  return refine.IsValid(error);
}

Eigen::Matrix4f TrackSet::Track::PredictedAt(double t_s) const {
  if (!(motion_dt_s > 0)) return pose;
  // The last motion scaled to the time since the last pose (a dropped frame doubles it), at
  // most three times over.
  const float r = static_cast<float>(std::clamp((t_s - time_s) / motion_dt_s, 0.0, 3.0));
  const Eigen::AngleAxisf turn(Eigen::Matrix3f(motion.topLeftCorner<3, 3>()));
  Eigen::Matrix4f scaled = Eigen::Matrix4f::Identity();
  scaled.topLeftCorner<3, 3>() = Eigen::AngleAxisf(turn.angle() * r, turn.axis()).matrix();
  scaled.topRightCorner<3, 1>() = motion.topRightCorner<3, 1>() * r;
  return scaled * pose;
}

bool TrackSet::ModelHeld(int model) const {
  return std::any_of(tracks_.begin(), tracks_.end(),
                     [&](const Track& t) { return t.model == model && Held(t); });
}

bool TrackSet::Due(const Track& t) const {
  return Held(t) && (t.frames_since_check + 1 >= options_.recheck_every ||
                     t.fitness < options_.recheck_below_fitness);
}

bool TrackSet::RecheckDue() const {
  return std::any_of(tracks_.begin(), tracks_.end(), [&](const Track& t) { return Due(t); });
}

bool TrackSet::AnyHeld() const {
  return std::any_of(tracks_.begin(), tracks_.end(), [&](const Track& t) { return Held(t); });
}

// The due track a score drop made due first, then the one longest without a check.
const TrackSet::Track* TrackSet::MostOverdue() const {
  const Track* most = nullptr;
  const auto urgency = [&](const Track& t) {
    return (t.fitness < options_.recheck_below_fitness ? 1000000 : 0) + t.frames_since_check;
  };
  for (const Track& t : tracks_)
    if (Due(t) && (!most || urgency(t) > urgency(*most))) most = &t;
  return most;
}

std::optional<Eigen::Vector3f> TrackSet::RecheckAt() const {
  const Track* t = options_.enabled ? MostOverdue() : nullptr;
  if (!t || std::size_t(t->model) >= centroids_.size()) return std::nullopt;
  return CentroidOf(t->pose, centroids_[std::size_t(t->model)]);
}

bool TrackSet::NeedsRecognition() const {
  if (!options_.enabled || tracks_.empty()) return true;
  if (RecheckDue()) return true;
  // Nothing held: attention searches (the fovea at the lost track, G growing) and recognition
  // runs every frame. While a track is held, the others' models are swept for.
  if (!AnyHeld()) return true;
  return SweepPhase() >= 0;
}

int TrackSet::SweepPhase() const {
  if (!options_.enabled || RecheckDue()) return -1;
  if (!AnyHeld()) return -1;  // attention's own search
  for (std::size_t m = 0; m < unheld_frames_.size(); ++m)
    if (!ModelHeld(static_cast<int>(m)) && unheld_frames_[m] + 1 >= options_.recheck_every)
      return sweeps_;
  return -1;
}

std::vector<bool> TrackSet::ModelsToRecognize() const {
  if (!options_.enabled || !AnyHeld()) return {};
  std::vector<bool> wanted(unheld_frames_.size(), false);
  if (const Track* t = MostOverdue()) {
    if (std::size_t(t->model) < wanted.size()) wanted[std::size_t(t->model)] = true;
    return wanted;
  }
  for (std::size_t m = 0; m < wanted.size(); ++m) wanted[m] = !ModelHeld(static_cast<int>(m));
  return wanted;
}

void TrackSet::Refine(const TrackFrame& frame, const std::vector<TrackModel>& models, Track* t,
                      std::string* events) {
  TrackResult r;
  const bool usable = FrameUsable(frame);
  if (usable) {
    TrackOptions o = options_.refine;
    if (t->rewatched) o.min_in_image_to_turn = 1;  // as Watch found it
    r = TrackPose(*models[std::size_t(t->model)].points, *frame.cloud, frame.intrinsics,
                  t->PredictedAt(frame.time_s), o);
  }
  t->fitness = r.fitness;
  t->coverage = r.coverage;
  const bool left_view = r.tracking && r.in_image < kMinInImageToHold;
  if (!r.tracking || left_view) {
    t->state = TrackState::kLost;
    t->lost_seq = frame.seq;
    // A track the watch took back and recognition never confirmed is not watched again: at the
    // image's edge (where re-checks are excused) it would come and go without end.
    t->watched = usable && !t->rewatched;
    char share[80];
    std::snprintf(share, sizeof share, "track %d lost (out of the image: %.0f%% in view)", t->id,
                  100 * r.in_image);
    Say(events, !usable ? "track " + std::to_string(t->id) + " lost (the frame is not organized)"
                : left_view ? std::string(share)
                            : Figures("lost", t->id, r.fitness, r.coverage));
    return;
  }
  t->motion = r.model_to_camera * t->pose.inverse();
  if (r.turn_held) {
    // A held turn is the prediction's: taken again on every frame it would spin an object that
    // waits at the image's edge. The centroid's move is the motion.
    const Eigen::Vector3f& c = models[std::size_t(t->model)].centroid;
    t->motion = Eigen::Matrix4f::Identity();
    t->motion.topRightCorner<3, 1>() = CentroidOf(r.model_to_camera, c) - CentroidOf(t->pose, c);
  }
  t->motion_dt_s = frame.time_s - t->time_s;
  t->pose = r.model_to_camera;
  if (r.in_image >= options_.refine.min_in_image_to_turn) t->inward_pose = t->pose;
  t->time_s = frame.time_s;
  t->state = TrackState::kTracking;
  ++t->frames_since_check;
}

void TrackSet::Tentative(Track* t, bool watched_back) const {
  t->state = TrackState::kReacquired;
  // Tentative: re-checked on the next frame, where one miss loses it.
  t->frames_since_check = options_.recheck_every;
  t->unconfirmed = options_.unconfirmed_rechecks - 1;
  t->lost_seq = -1;
  t->rewatched = watched_back;
  t->motion = Eigen::Matrix4f::Identity();
  t->motion_dt_s = 0;
}

void TrackSet::Watch(const TrackFrame& frame, const std::vector<TrackModel>& models, Track* t,
                     std::string* events) {
  // From where it was lost, and from where it was last well inside the image (an object
  // coming back the way it left is seen there first).
  const VerificationModel& model = *models[std::size_t(t->model)].points;
  const auto holds = [](const TrackResult& r) {
    return r.tracking && r.in_image >= kMinInImageToWatch;
  };
  TrackOptions o = options_.refine;
  o.min_in_image_to_turn = 1;  // part of it in view: its turn is the one it was lost with
  TrackResult r = TrackPose(model, *frame.cloud, frame.intrinsics, t->pose, o);
  if (!holds(r) && !t->inward_pose.isIdentity() && !t->inward_pose.isApprox(t->pose))
    r = TrackPose(model, *frame.cloud, frame.intrinsics, t->inward_pose, o);
  if (!holds(r)) return;
  const int lost_for = static_cast<int>(frame.seq - t->lost_seq);
  Tentative(t, /*watched_back=*/true);
  t->pose = r.model_to_camera;
  t->time_s = frame.time_s;
  t->fitness = r.fitness;
  t->coverage = r.coverage;
  t->watched = false;
  t->first_check = false;
  // What it is published with: the frame's support, not a recognition's.
  Detection& found = t->found;
  found = Detection{};
  found.model = t->model;
  found.model_to_scene = t->pose;
  found.centroid_m = CentroidOf(t->pose, models[std::size_t(t->model)].centroid);
  found.fitness = r.fitness;
  found.coverage = r.coverage;
  found.confidence = TrackScore(r.fitness, r.coverage);
  Say(events,
      Figures(
          ("re-acquired where it was lost after " + std::to_string(lost_for) + " frames").c_str(),
          t->id, r.fitness, r.coverage));
}

Detection TrackSet::Publish(const Track& t, const std::vector<TrackModel>& models) const {
  Detection d;
  d.model = t.model;
  d.model_to_scene = t.pose;
  d.centroid_m = CentroidOf(t.pose, models[std::size_t(t.model)].centroid);
  d.track_id = t.id;
  d.track_state = t.state;
  if (t.state == TrackState::kReacquired) {  // recognition's figures for what it found
    d.votes = t.found.votes;
    d.fitness = t.found.fitness;
    d.coverage = t.found.coverage;
    d.colour_agreement = t.found.colour_agreement;
    d.texture_agreement = t.found.texture_agreement;
    d.confidence = t.found.confidence;
  } else if (t.state == TrackState::kTracking) {
    d.fitness = t.fitness;
    d.coverage = t.coverage;
    d.confidence = TrackScore(t.fitness, t.coverage);
  } else {
    d.confidence = 0;
  }
  return d;
}

// One frame's recognized instances matched to the tracks: TrackSet::Update's three steps.
class TrackSet::Matching {
 public:
  Matching(TrackSet* set, const TrackFrame& frame, const std::vector<TrackModel>& models,
           const std::vector<Detection>& recognized, std::string* events)
      : set_(*set),
        frame_(frame),
        models_(models),
        recognized_(recognized),
        events_(events),
        order_(recognized.size()),
        taken_(set->tracks_.size(), false),
        ambiguous_(set->tracks_.size(), false),
        used_(recognized.size(), false) {
    // Recognition's instances, most confident first, each to one track at most.
    std::iota(order_.begin(), order_.end(), std::size_t{0});
    std::stable_sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
      return recognized[a].confidence > recognized[b].confidence;
    });
  }

  // 1. Instances that agree with a held track confirm it.
  void ConfirmHeld() {
    for (std::size_t k : order_) {
      const Detection& d = recognized_[k];
      for (std::size_t i = 0; i < tracks().size() && !used_[k]; ++i) {
        Track& t = tracks()[i];
        if (t.model != d.model || taken_[i] || Distance(t, d) > options().same_track_m) continue;
        if (t.state == TrackState::kTracking) {
          taken_[i] = used_[k] = true;
          t.frames_since_check = 0;
          t.unconfirmed = 0;
          t.rewatched = false;
          if (t.first_check)
            Retake(&t, d);
          else
            Realign(&t, d);
        } else if (t.state == TrackState::kLost) {  // lost this frame, yet recognized here
          Reacquire(i, d, "re-acquired by recognition");
          used_[k] = true;
        }
      }
    }
  }

  // 2. The others. Where another model's track stands, the instance is that object seen as
  // a look-alike: not tracked. Else a track of its model that is lost, the nearest first (far
  // from its last held pose only a confident instance moves it: MayMove). Else a held track
  // recognition looked at and did not find: a confident instance puts it back (it slid off
  // its object); a less confident one near it is its object at a worse pose (a can turned
  // about its axis), which neither confirms the track nor counts against it. Else a new track.
  void PlaceTheOthers() {
    for (std::size_t k : order_) {
      if (used_[k]) continue;
      const Detection& d = recognized_[k];
      if (Occupied(d)) {
        untracked.push_back(d);  // published as recognition found it, not tracked (state NONE)
        continue;
      }
      if (TakenByLostTrack(k) || TakenByHeldTrack(k)) continue;
      StartTrack(k);
    }
  }

  // 3. Held tracks recognition looked at (inside where it searched: a track outside stays
  // due, and is re-checked when the fovea visits it) and did not find.
  void MissTheUnfound() {
    for (std::size_t i = 0; i < tracks().size(); ++i) {
      Track& t = tracks()[i];
      // The first recognized frame after a find was its one chance to be retaken.
      if (t.found_s != frame_.time_s) t.first_check = false;
      if (!set_.Held(t) || taken_[i] || !InsideSearch(t)) continue;
      t.frames_since_check = 0;
      if (ambiguous_[i] || CutOffByTheView(t)) continue;
      if (++t.unconfirmed >= options().unconfirmed_rechecks) {
        t.state = TrackState::kLost;
        t.lost_seq = frame_.seq;
        t.watched = false;  // recognition says it is not there: not to be taken back unchecked
        Say(events_, "track " + std::to_string(t.id) + " lost (not confirmed by " +
                         std::to_string(t.unconfirmed) + " re-checks)");
      }
    }
  }

  std::vector<Detection> untracked;  // instances no track took, published as they were found

 private:
  std::vector<Track>& tracks() { return set_.tracks_; }
  const TrackingOptions& options() const { return set_.options_; }

  float Distance(const Track& t, const Detection& d) const {
    return (CentroidOf(t.pose, models_[std::size_t(t.model)].centroid) - d.centroid_m).norm();
  }
  // Whether the frame's recognition looked where track `t` stands.
  // Whether the image's edge cuts the track's model off (its bounding sphere reaches past
  // it): recognition cannot confirm an object it sees only part of, and a re-check that does
  // not find it there says nothing against the track.
  bool CutOffByTheView(const Track& t) const {
    const VerificationModel* m = models_[std::size_t(t.model)].points;
    if (!m || m->radius_m <= 0) return false;
    const Eigen::Vector3f c = CentroidOf(t.pose, m->centre);  // of its bounding box
    const float r = m->radius_m;
    if (c.z() - r <= 0.05f) return true;
    const CameraIntrinsics& k = frame_.intrinsics;
    const Eigen::Vector2d uv = k.Project(c);
    const double r_px = std::max(k.fx, k.fy) * r / c.z();
    return uv.x() - r_px < 0 || uv.y() - r_px < 0 || uv.x() + r_px >= k.width ||
           uv.y() + r_px >= k.height;
  }
  bool InsideSearch(const Track& t) const {
    if (frame_.sweep) return false;  // a sweep's window need not hold the tracks
    const std::vector<bool>& ran = frame_.recognized_models;
    if (std::size_t(t.model) < ran.size() && !ran[std::size_t(t.model)]) return false;
    if (frame_.searched_half_m < 0) return true;
    const Eigen::Vector3f c = CentroidOf(t.pose, models_[std::size_t(t.model)].centroid);
    return ((c - frame_.searched_centre_m).array().abs() <= frame_.searched_half_m).all();
  }
  // Whether instance `d` may re-acquire the lost track `t`: near its last held pose, or as
  // confident as a second track must be.
  bool MayMove(const Track& t, const Detection& d) const {
    return Distance(t, d) <= options().reacquire_radius_m ||
           d.confidence >= options().min_extra_track_confidence;
  }
  // Whether another model's held track stands where `d` is.
  bool Occupied(const Detection& d) const {
    return std::any_of(set_.tracks_.begin(), set_.tracks_.end(), [&](const Track& t) {
      return t.model != d.model && set_.Held(t) && Distance(t, d) <= options().same_track_m;
    });
  }

  // Instance k to the nearest lost track of its model that it may move.
  bool TakenByLostTrack(std::size_t k) {
    const Detection& d = recognized_[k];
    std::size_t best = tracks().size();
    for (std::size_t i = 0; i < tracks().size(); ++i) {
      const Track& t = tracks()[i];
      if (t.model != d.model || taken_[i] || set_.Held(t) || !MayMove(t, d)) continue;
      if (best == tracks().size() || Distance(t, d) < Distance(tracks()[best], d)) best = i;
    }
    if (best == tracks().size()) return false;
    Reacquire(best, d, "re-acquired by recognition");
    used_[k] = true;
    return true;
  }

  // Instance k, confident, puts back a held track of its model that recognition did not find;
  // less confident and near one, it leaves that track neither confirmed nor missed.
  bool TakenByHeldTrack(std::size_t k) {
    const Detection& d = recognized_[k];
    for (std::size_t i = 0; i < tracks().size() && !used_[k]; ++i) {
      const Track& t = tracks()[i];
      if (t.model != d.model || taken_[i] || !set_.Held(t) || !InsideSearch(t)) continue;
      if (d.confidence >= options().min_extra_track_confidence) {
        char why[96];
        std::snprintf(why, sizeof why, "put back by recognition (%.1f cm off)",
                      100.0f * Distance(t, d));
        Reacquire(i, d, why);
        used_[k] = true;
      } else if (Distance(t, d) <= options().reacquire_radius_m) {
        ambiguous_[i] = true;
      }
    }
    return used_[k];
  }

  // Instance k as a new track, when it is confident enough and there is room; else untracked.
  void StartTrack(std::size_t k) {
    const Detection& d = recognized_[k];
    const bool model_tracked = std::any_of(tracks().begin(), tracks().end(),
                                           [&](const Track& o) { return o.model == d.model; });
    const float bar = model_tracked     ? options().min_extra_track_confidence
                      : frame_.attended ? 0.0f
                                        : options().min_track_confidence;
    if (static_cast<int>(tracks().size()) >= options().max_tracks || d.confidence < bar) {
      untracked.push_back(d);  // published as recognition found it, not tracked (state NONE)
      return;
    }
    Track t;
    t.id = set_.next_id_++;
    t.model = d.model;
    tracks().push_back(t);
    taken_.push_back(false);
    ambiguous_.push_back(false);
    char found[64];
    std::snprintf(found, sizeof found, "found (confidence %.2f%s)", d.confidence,
                  frame_.attended ? ", the best of a search" : "");
    Reacquire(tracks().size() - 1, d, found);
    used_[k] = true;
  }

  // Takes instance `d` for track i: a held track it agrees with keeps its refined pose; any
  // other starts again from recognition's pose, refined on this frame when the frame holds it.
  void Reacquire(std::size_t i, const Detection& d, const char* why) {
    Track& t = tracks()[i];
    const bool put_back = set_.Held(t);
    taken_[i] = true;
    const int lost_for = t.lost_seq >= 0 ? static_cast<int>(frame_.seq - t.lost_seq) : 0;
    // Its motion: between its last two sightings by recognition when they are recent and tell
    // a move (MoveBetweenSightings); else, held until this frame (lost on it) and found again
    // near, from its last pose to recognition's (a fast object outruns a track that starts
    // still).
    const bool was_held = t.lost_seq == frame_.seq;  // a new track's is -1
    const Eigen::Matrix4f last = t.pose;
    const double last_s = t.time_s;
    set_.Tentative(&t, /*watched_back=*/false);
    const TrackModel& model = models_[std::size_t(t.model)];
    // A put-back corrects a held track's pose, not its motion; a re-acquisition farther than
    // reacquire_radius_m may be another instance of the model.
    const bool sighted = !put_back && MoveBetweenSightings(&t, d, options().reacquire_radius_m);
    t.fitness = d.fitness;
    t.coverage = d.coverage;
    TakePose(&t, d);
    t.first_check = true;
    const float moved =
        (CentroidOf(t.pose, model.centroid) - CentroidOf(last, model.centroid)).norm();
    if (!sighted && was_held && frame_.time_s > last_s && moved <= options().reacquire_radius_m) {
      t.motion = t.pose * last.inverse();
      t.motion_dt_s = frame_.time_s - last_s;
    }
    std::string what = "track " + std::to_string(t.id) + " " + why;
    if (lost_for > 0) what += " after " + std::to_string(lost_for) + " frames";
    Say(events_, what);
  }

  // Recognition's pose of `d` for track t, refined on this frame when the frame holds it;
  // the track's sighting from now on. Returns the refinement (not tracking when there was none).
  TrackResult TakePose(Track* t, const Detection& d) {
    t->found = d;
    t->found_s = frame_.time_s;
    t->pose = d.model_to_scene;
    TrackResult r;
    if (FrameUsable(frame_)) {
      r = TrackPose(*models_[std::size_t(t->model)].points, *frame_.cloud, frame_.intrinsics,
                    t->pose, options().refine);
      if (r.tracking) t->pose = r.model_to_camera;
    }
    if (r.in_image >= options().refine.min_in_image_to_turn) t->inward_pose = t->pose;
    t->time_s = frame_.time_s;
    return r;
  }

  // The track's motion from its last sighting by recognition to `d`, when that sighting is
  // recent and the object moved between the two more than recognition's poses of a still
  // object differ (kMinSightedMoveM), at most `max_move_m`, and no faster than an object is
  // thrown: the centroid's move (a symmetric object's two poses may be two of its turns). Two
  // sightings are unbiased where a track's own poses lag a fast object it started from still.
  // False, and nothing set, otherwise.
  bool MoveBetweenSightings(Track* t, const Detection& d,
                            float max_move_m = std::numeric_limits<float>::infinity()) const {
    const double dt = frame_.time_s - t->found_s;
    if (!(dt > 0) || dt > kSightingsApartMaxS) return false;  // NaN: never sighted
    const float moved = (d.centroid_m - t->found.centroid_m).norm();
    if (moved <= kMinSightedMoveM || moved > max_move_m) return false;
    if (moved > kMaxSpeedMps * float(dt)) return false;
    t->motion = Eigen::Matrix4f::Identity();
    t->motion.topRightCorner<3, 1>() = d.centroid_m - t->found.centroid_m;
    t->motion_dt_s = dt;
    return true;
  }

  // The re-check right after a track was found confirms it: the two sightings give it its
  // motion, and recognition's pose, when the frame holds it, replaces the one tracking reached
  // from a still start (with its score: the track publishes it).
  void Retake(Track* t, const Detection& d) {
    t->first_check = false;
    if (!MoveBetweenSightings(t, d)) return;
    const Eigen::Matrix4f tracked = t->pose, inward = t->inward_pose;
    const TrackResult r = TakePose(t, d);
    if (!r.tracking || AtImageEdge(r, Score(*t, tracked))) {
      t->pose = tracked;
      t->inward_pose = inward;
      return;
    }
    t->fitness = r.fitness;
    t->coverage = r.coverage;
  }

  // A confirmed track takes recognition's pose, refined on the frame, when that lays more of
  // the model on the frame than the track's own pose: tracking can slide along an object's
  // faces (a cube cut from one view misses a face that would stop it) where recognition,
  // which matches the whole shape, does not. Not at the image's edge (AtImageEdge).
  void Realign(Track* t, const Detection& d) {
    if (!FrameUsable(frame_)) return;
    const VerificationModel& m = *models_[std::size_t(t->model)].points;
    const TrackResult r =
        TrackPose(m, *frame_.cloud, frame_.intrinsics, d.model_to_scene, options().refine);
    if (!r.tracking) return;
    const TrackResult own = Score(*t, t->pose);
    if (AtImageEdge(r, own) || r.inliers <= own.inliers) return;
    t->pose = r.model_to_camera;
    t->fitness = r.fitness;
    t->coverage = r.coverage;
  }

  // The track's model at `pose`, scored on this frame as it stands.
  TrackResult Score(const Track& t, const Eigen::Matrix4f& pose) const {
    return ScorePose(*models_[std::size_t(t.model)].points, *frame_.cloud, frame_.intrinsics, pose,
                     options().refine);
  }

  // Recognition's pose `r` (refined) against the track's own (scored as `own`), where either
  // puts too little of the object in the image for the tracker to turn it: there recognition's
  // turn went unchecked, and a pose wins the comparison by turning more of the model into view.
  // The track keeps its own.
  bool AtImageEdge(const TrackResult& r, const TrackResult& own) const {
    return r.turn_held || own.in_image < options().refine.min_in_image_to_turn;
  }

  TrackSet& set_;
  const TrackFrame& frame_;
  const std::vector<TrackModel>& models_;
  const std::vector<Detection>& recognized_;
  std::string* events_;
  std::vector<std::size_t> order_;  // recognized_'s indices, most confident first
  std::vector<bool> taken_;         // per track: an instance of this frame took it
  std::vector<bool> ambiguous_;     // per track: a weaker instance near it (step 2)
  std::vector<bool> used_;          // per instance: a track took it
};

void TrackSet::ForgetLongSearches(std::int64_t seq, std::string* events) {
  // Lost last frame: searching now; searched too long: forgotten.
  for (Track& t : tracks_)
    if (t.state == TrackState::kLost) t.state = TrackState::kSearching;
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const Track& t) {
                                 const bool forget =
                                     t.state == TrackState::kSearching &&
                                     seq - t.lost_seq >= options_.forget_after_frames;
                                 if (forget)
                                   Say(events, "track " + std::to_string(t.id) + " forgotten");
                                 return forget;
                               }),
                tracks_.end());
}

void TrackSet::CountUnheldFrames(const std::vector<TrackModel>& models, bool sweep) {
  centroids_.clear();
  for (const TrackModel& m : models) centroids_.push_back(m.centroid);
  unheld_frames_.resize(models.size(), 0);
  for (std::size_t m = 0; m < models.size(); ++m)
    unheld_frames_[m] = ModelHeld(static_cast<int>(m)) || sweep ? 0 : unheld_frames_[m] + 1;
}

std::vector<Detection> TrackSet::Update(const TrackFrame& frame,
                                        const std::vector<TrackModel>& models,
                                        const std::vector<Detection>& recognized,
                                        std::string* events) {
  if (!options_.enabled) return recognized;
  ForgetLongSearches(frame.seq, events);
  for (Track& t : tracks_)
    if (Held(t)) Refine(frame, models, &t, events);
  if (frame.sweep) ++sweeps_;
  std::vector<Detection> untracked;
  if (frame.recognized) {
    Matching matching(this, frame, models, recognized, events);
    matching.ConfirmHeld();
    matching.PlaceTheOthers();
    matching.MissTheUnfound();
    untracked = std::move(matching.untracked);
  }
  // After recognition's instances: a track they did not take back is watched, and one the
  // watch takes back is re-checked on the next frame, not judged by this frame's recognition.
  for (Track& t : tracks_)
    if (t.state == TrackState::kSearching && t.watched && FrameUsable(frame) &&
        frame.seq - t.lost_seq <= options_.watch_lost_frames)
      Watch(frame, models, &t, events);
  CountUnheldFrames(models, frame.sweep);  // the sweep clock of the models no track holds
  std::vector<Detection> tracked;
  tracked.reserve(tracks_.size() + untracked.size());
  for (const Track& t : tracks_) tracked.push_back(Publish(t, models));
  tracked.insert(tracked.end(), untracked.begin(), untracked.end());
  return tracked;
}

}  // namespace saccade
