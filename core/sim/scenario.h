// Synthetic scenarios: a target and clutter on a table, moving along trajectories, rendered
// frame by frame by the synthetic Kinect with the ground truth of every frame. Pure: a
// scenario is a value and frame i is a function of it and i.
#pragma once

#include "core/frame.h"
#include "core/sim/synthetic.h"

#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// A motion on the table plane: the position (x, z of the camera frame at t = 0) and the yaw
/// about the table's normal as functions of time t (seconds).
struct Trajectory {
  enum class Kind {
    kStatic,       // stays at start
    kLinear,       // start + velocity t
    kCircular,     // around `centre` at `radius`, one turn per `period_s`, starting at angle 0
    kLeaveReturn,  // out along velocity for half of `period_s`, back for the other half
  } kind = Kind::kStatic;
  Eigen::Vector2f start_xz_m = Eigen::Vector2f::Zero();
  Eigen::Vector2f velocity_xz_mps = Eigen::Vector2f::Zero();
  Eigen::Vector2f centre_xz_m = Eigen::Vector2f::Zero();
  float radius_m = 0.0f;
  float period_s = 10.0f;
  float yaw_rad = 0.0f;         // at t = 0
  float yaw_rate_radps = 0.0f;  // turning while moving

  Eigen::Vector2f PositionAt(double t_s) const;
  float YawAt(double t_s) const;

  /// The keys of a scenario's `target_motion` and `camera_motion` sections (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Choice("kind", &kind,
              {{"static", Kind::kStatic},
               {"linear", Kind::kLinear},
               {"circular", Kind::kCircular},
               {"leave-return", Kind::kLeaveReturn}});
    a->Visit("start_xz_m", &start_xz_m);
    a->Visit("velocity_xz_mps", &velocity_xz_mps);
    a->Visit("centre_xz_m", &centre_xz_m);
    a->Visit("radius_m", &radius_m);
    a->Visit("period_s", &period_s);
    a->Visit("yaw_rad", &yaw_rad);
    a->Visit("yaw_rate_radps", &yaw_rate_radps);
  }
};

/// The most frames a scenario or a capture sequence may have (a day at 30 Hz is 2.6 M).
constexpr int kMaxSequenceFrames = 10'000'000;

/// Everything that makes a sequence. Frame i is captured at t = i / rate_hz.
struct Scenario {
  std::string name;
  int frames = 90;
  double rate_hz = 30.0;
  std::uint32_t seed = 1;
  float table_height_m = 0.3f;  // the camera is this far above the table plane
  Shape target = TargetShape();
  float target_bottom_y_m = 0.05f;  // where the target's bottom face is in its own frame
  Trajectory target_motion;
  /// The camera pans (yaw) and slides parallel to the table; its height stays the same.
  Trajectory camera_motion;
  struct Clutter {
    Shape shape;
    Eigen::Vector2f xz_m = Eigen::Vector2f::Zero();  // where it stands (camera frame at t = 0)
    float yaw_rad = 0.0f;
    float bottom_y_m = 0.05f;
  };
  std::vector<Clutter> clutter;
  /// Frames [occluded_from, occluded_from + occluded_frames) have a screen between the camera
  /// and the target.
  int occluded_from = -1;
  int occluded_frames = 0;
  KinectNoise noise;
  /// Paper protocol (§5.2): frame i shows only the first min(i, clutter.size()) clutter
  /// objects, so clutter grows along the sequence.
  bool clutter_grows = false;

  bool IsValid(std::string* error) const;
};

/// The label of the target's pixels in a scenario's frames (clutter: 2, 3, ...).
constexpr std::uint32_t kTargetLabel = 1;

/// The truth of one frame, in the camera frame of that frame.
struct ScenarioFrame {
  RenderedFrame rendered;
  GroundTruth truth;
  double time_s = 0.0;
};

/// A trajectory's pose at time t: its position on the x-z plane and its yaw about y (a
/// scenario's camera X_WC, a capture sequence's camera or object motion).
Eigen::Isometry3f PlanarPose(const Trajectory& motion, double t);

/// The target's true pose X_CO in frame `index` (no rendering: cheap for checking a run).
Eigen::Isometry3f ScenarioTargetPose(const Scenario& scenario, int index);

/// Renders frame `index` (0 <= index < scenario.frames) of a valid scenario.
ScenarioFrame RenderScenarioFrame(const Scenario& scenario, int index,
                                  const CameraIntrinsics& intrinsics = {});

/// Named presets: static, linear, circular, occluded, leave-return, paper-protocol. nullopt
/// for an unknown name.
std::optional<Scenario> ScenarioPreset(const std::string& name);
std::vector<std::string> ScenarioPresetNames();

/// The demo's recognition case: a model cut from one capture of the target alone, and a
/// second capture (the `static` preset's first frame: the target among its clutter) where the
/// target has moved and turned. `truth` is X_CO of the target in `scene`, mapping model
/// coordinates into the scene's camera frame.
struct CrossCaptureCase {
  Cloud model;
  RenderedFrame scene;
  Eigen::Isometry3f truth = Eigen::Isometry3f::Identity();
  int clutter_objects = 0;
};
/// A model of a scenario's target as a user would make one: the target alone (no clutter, no
/// occluder) captured once by the synthetic Kinect with `seed`, cut out, in its own frame.
Cloud CaptureTargetModel(Scenario scenario, std::uint32_t seed,
                         const CameraIntrinsics& intrinsics = {});

/// The paper-protocol ball's model, captured from 0.9 m (synthetic:ball).
Cloud SyntheticBallModel(std::uint32_t seed, const CameraIntrinsics& intrinsics = {});

/// The synthetic target's model as a user would make it: the target alone, captured once by
/// the synthetic Kinect (seeded) from its own viewpoint, cut out and expressed in its frame.
Cloud SyntheticTargetModel(std::uint32_t seed, const CameraIntrinsics& intrinsics = {});

CrossCaptureCase MakeDemoCase(std::uint32_t seed, const CameraIntrinsics& intrinsics = {});

/// The centre of a shape's bounding box, in its own frame.
Eigen::Vector3f ShapeCentre(const Shape& shape);

}  // namespace saccade
