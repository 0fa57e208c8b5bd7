// Values passed between Saccade's stages. Units are metres and seconds unless a name says
// otherwise; clouds are in the camera optical frame (x right, y down, z forward).
#pragma once

#include "core/camera.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

/// The point type of every cloud Saccade handles (XYZ plus packed colour; colour may be unset).
using PointT = pcl::PointXYZRGBA;
using Cloud = pcl::PointCloud<PointT>;

/// True when the point has coordinates (an organized cloud's holes are NaN).
inline bool FinitePoint(const PointT& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

/// An axis-aligned box [min, max] in some frame (which the owner names). Empty when any
/// max < min.
struct Box {
  Eigen::Vector3f min = Eigen::Vector3f::Zero();
  Eigen::Vector3f max = Eigen::Vector3f::Zero();

  bool Empty() const { return (max.array() < min.array()).any(); }
  /// Closed interval test: a point on a face is inside.
  bool Contains(const Eigen::Vector3f& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  /// True when `inner` lies entirely inside this box (an empty box lies inside any box).
  bool ContainsBox(const Box& inner) const {
    return inner.Empty() ||
           ((inner.min.array() >= min.array()).all() && (inner.max.array() <= max.array()).all());
  }
  Eigen::Vector3f Size() const { return max - min; }
};

/// Where a tracked object stands in a frame (instance_t's track_state; attention/tracks.h).
/// kNone: recognition's instance, not tracked (tracking is off, max_tracks are held, a second
/// instance of a tracked model below tracking.min_extra_track_confidence, one far from where
/// its model's track was lost: tracking.reacquire_radius_m, or one where another model's track
/// stands). kTracking: refined from
/// the last frame and the frame supports it. kLost: this frame no longer supports it (published
/// once, at the last pose). kSearching: lost for more than one frame, attention searching.
/// kReacquired: recognition found it this frame (first found, after a loss, or a track that
/// slid off its object put back).
enum class TrackState { kNone = 0, kTracking = 1, kLost = 2, kSearching = 3, kReacquired = 4 };

/// An instance to act on (and for attention to follow): with `tracking` on, one a track holds
/// (not a lost track's last pose, nor an instance the tracks declined: a look-alike); with it
/// off, every instance recognition found.
inline bool Actionable(TrackState s, bool tracking) {
  return tracking ? s == TrackState::kTracking || s == TrackState::kReacquired
                  : s != TrackState::kLost && s != TrackState::kSearching;
}

/// "NONE", "TRACKING", "LOST", "SEARCHING" or "RE-ACQUIRED".
inline const char* TrackStateName(TrackState s) {
  switch (s) {
    case TrackState::kNone:
      return "NONE";
    case TrackState::kTracking:
      return "TRACKING";
    case TrackState::kLost:
      return "LOST";
    case TrackState::kSearching:
      return "SEARCHING";
    case TrackState::kReacquired:
      return "RE-ACQUIRED";
  }
  return "?";
}

/// One recognized instance of the model in a scene.
struct Detection {
  int model = -1;  // index of the model it is an instance of, among those searched
  Eigen::Matrix4f model_to_scene = Eigen::Matrix4f::Identity();  // X_SM: model frame M in scene S
  int votes = 0;                                         // correspondences that agree on this pose
  Eigen::Vector3f centroid_m = Eigen::Vector3f::Zero();  // model centroid in the scene frame
  /// Set by verification (-1 when not verified): the share of the model's visible points that lie
  /// on the scene surface, the share of all its points that do, and the share of those whose
  /// colour agrees (-1 when not checked).
  float fitness = -1;
  float coverage = -1;
  float colour_agreement = -1;
  /// The correlation of brightness between the model points on the scene's surface and the scene
  /// points they lie on, in [-1, 1]: printed patterns line up only on the object itself, at its
  /// pose (-1 when not measured: no colour, or a surface too plain on either side to tell).
  float texture_agreement = -1;
  /// The share of the places just outside its outline where the scene continues its surface
  /// (ContinuedShare, core/verification.h): near 1 for a patch of a larger surface; -1 when not
  /// measured (no organized frame).
  float continued = -1;
  /// How likely the instance is to be the object, in [0, 1], from its verification figures
  /// (calibrated on the cross-capture benchmark, docs/RESULTS.md); -1 when not verified.
  float confidence = -1;
  /// (model keypoint index, scene keypoint index) pairs behind this instance.
  std::vector<std::pair<int, int>> correspondences;
  /// The track it belongs to (stable across frames, -1 when tracking is off) and its state.
  int track_id = -1;
  TrackState track_state = TrackState::kNone;
};

/// What one processed frame produced: every model's instances and how the frame was searched
/// (SACCADE_DETECTIONS). Positions are in the camera frame.
struct FrameDetections {
  std::int64_t seq = 0;                // the frame's sequence number
  std::int64_t capture_utime = 0;      // the frame's capture time (Frame::capture_utime)
  std::int64_t arrival_steady_ns = 0;  // when it reached the host (Frame::arrival_steady_ns)
  bool foveated = true;                // false: the whole frame was searched
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();  // the fovea this frame was foveated at
  float growth_m = 0;                                 // G it was foveated with
  std::int64_t fixation_seq = -1;                     // the frame whose fixation was used
  float recognize_ms = 0;  // foveation and recognition of every model (0: tracked alone)
  float track_ms = 0;      // refining every track and taking recognition's instances
  std::vector<Detection> instances;
  std::vector<std::string> models;  // the searched models' names, indexed by Detection::model
  std::vector<Eigen::Vector3f> model_extents_m;  // their sizes along their own axes, likewise
};

}  // namespace saccade
