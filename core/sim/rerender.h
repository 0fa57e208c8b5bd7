// New frames from a real capture (issue 16's real-data sequences): a captured organized frame
// is the world, and a virtual camera near the original viewpoint sees it again, its points
// splatted into a z-buffer, so the holes, shadows and sensor noise are the capture's own. One
// labelled object may move rigidly through it. Pure.
#pragma once

#include "core/camera.h"
#include "core/frame.h"
#include "core/schema.h"
#include "core/sim/scenario.h"
#include "core/types.h"

#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

/// What moves and where the virtual camera is, all in the capture's camera frame W.
struct RerenderPose {
  Eigen::Isometry3f X_WC = Eigen::Isometry3f::Identity();  // the virtual camera C in W
  /// The indices (into the capture) of one object's points, and the rigid motion applied to
  /// them in W (identity: the object stays where it was captured).
  std::vector<int> object;
  Eigen::Isometry3f object_motion_W = Eigen::Isometry3f::Identity();
  /// Further objects' point indices, which stay where they were captured: `labels` marks
  /// their pixels 2 + j for others[j].
  std::vector<std::vector<int>> others;
};

/// Renders the capture `world` (an organized frame, camera frame W = its own) as the camera at
/// pose.X_WC with intrinsics `k` sees it: each finite point is splatted over the pixels its
/// capture footprint covers at its new depth (one pixel at the captured depth, more when the
/// camera came nearer), the nearest point winning each pixel. `labels`, when given, gets per
/// pixel 1 where the object's points won, 2 + j where others[j]'s did, and 0 elsewhere. Pixels
/// nothing reaches are NaN.
Cloud RerenderCapture(const Cloud& world, const CameraIntrinsics& k, const RerenderPose& pose,
                      std::vector<std::uint8_t>* labels = nullptr);

/// A sequence made from one real capture: the virtual camera's motion and one labelled
/// object's (both Trajectory: positions on the capture's x-z plane, yaw about its y axis; the
/// object's about its captured centroid, its start_xz_m the displacement at t = 0).
struct CaptureSequence {
  std::string name;
  std::string capture;  // a labelled PCD (mOSD), relative to the data folder
  int object = 1;       // mOSD object k: labels 10k..10k+9
  /// Further mOSD objects, staying where they were captured, whose truth every frame carries
  /// too (GroundTruth::others, in this order): sequences with several objects to track.
  std::vector<int> others;
  int frames = 90;
  double rate_hz = 30.0;
  Trajectory camera_motion;
  Trajectory object_motion;
  /// Frames [occluded_from, occluded_from + occluded_frames) have a board (occluder_size_m,
  /// width x height, facing the camera) occluder_distance_m in front of the object's centroid
  /// on the camera's line of sight to it: the object is hidden, the board is what is seen.
  int occluded_from = -1;
  int occluded_frames = 0;
  Eigen::Vector2f occluder_size_m{0.3f, 0.3f};
  float occluder_distance_m = 0.15f;

  bool IsValid(std::string* error) const;
  /// The keys of a capture sequence file (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("name", &name);
    a->Visit("capture", &capture);
    a->Visit("object", &object);
    a->Visit("others", &others);
    a->Visit("frames", &frames);
    a->Visit("rate_hz", &rate_hz);
    a->Visit("occluded_from", &occluded_from);
    a->Visit("occluded_frames", &occluded_frames);
    a->Visit("occluder_size_m", &occluder_size_m);
    a->Visit("occluder_distance_m", &occluder_distance_m);
    a->Section("camera_motion", &camera_motion);
    a->Section("object_motion", &object_motion);
  }
};

/// A capture loaded for re-rendering: its cloud, the object's point indices and centroid.
struct LoadedCapture {
  Cloud cloud;
  CameraIntrinsics intrinsics;
  std::vector<int> object;                                    // indices of the object's points
  Eigen::Vector3f object_centroid = Eigen::Vector3f::Zero();  // capture frame
  std::vector<std::vector<int>> others;          // the sequence's further objects' point indices
  std::vector<Eigen::Vector3f> other_centroids;  // and their centroids, capture frame
};

/// The indices of mOSD object k's finite points (labels 10k..10k+9) in a labelled capture.
std::vector<int> MosdObjectPoints(const Cloud& cloud, const std::vector<std::uint32_t>& labels,
                                  int object);

/// Frame `index` of the sequence: the capture seen from the camera at that time, with the
/// object moved, and the truth: X_CO of the object (O: the capture's camera frame, in which a
/// model cut from the capture is expressed), its centroid and its visible share; the same for
/// each of the sequence's others.
struct CaptureFrame {
  Cloud cloud;
  GroundTruth truth;
  double time_s = 0;
};
CaptureFrame RenderCaptureFrame(const CaptureSequence& sequence, const LoadedCapture& capture,
                                int index);

}  // namespace saccade
