#include "core/sim/scenario.h"

#include "core/fail.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

namespace saccade {

namespace {

constexpr double kTwoPi = 6.283185307179586;

Shape ScreenShape() {  // a board, 30 cm wide and 40 cm tall, standing on the table
  return Shape{{Shape::Part::Box({0, 0, 0}, {0.15f, 0.2f, 0.01f})}};
}

std::vector<Scenario::Clutter> DemoClutter() {
  using Part = Shape::Part;
  return {
      {Shape{{Part::Box({0, 0, 0}, {0.08f, 0.06f, 0.08f})}}, {-0.3f, 1.25f}, 0.3f, 0.06f},
      {Shape{{Part::Sphere({0, 0, 0}, 0.06f)}}, {0.35f, 1.3f}, 0.0f, 0.06f},
      {Shape{{Part::Box({0, 0, 0}, {0.035f, 0.09f, 0.035f})}}, {-0.4f, 0.8f}, 0.7f, 0.09f},
  };
}

// §5.2 of the paper: a ball among clutter that grows scene by scene. Twelve objects of mixed
// kinds and sizes, placed from the seed around the ball, never touching it.
std::vector<Scenario::Clutter> ProtocolClutter(std::uint32_t seed, const Eigen::Vector2f& ball) {
  using Part = Shape::Part;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Scenario::Clutter> out;
  while (out.size() < 12) {
    const Eigen::Vector2f xz(-0.45f + 0.9f * unit(rng), 0.75f + 0.8f * unit(rng));
    if ((xz - ball).norm() < 0.25f) continue;
    bool crowded = false;
    for (const auto& c : out) crowded = crowded || (c.xz_m - xz).norm() < 0.14f;
    if (crowded) continue;
    Scenario::Clutter c;
    c.xz_m = xz;
    c.yaw_rad = static_cast<float>(kTwoPi) * unit(rng);
    const float s = 0.03f + 0.04f * unit(rng);
    switch (out.size() % 3) {
      case 0:
        c.shape.parts.push_back(Part::Box({0, 0, 0}, {s, 0.8f * s + 0.02f, 0.7f * s}));
        c.bottom_y_m = 0.8f * s + 0.02f;
        break;
      case 1:  // balls, but clearly smaller than the 8 cm one sought (2-5 cm)
        c.shape.parts.push_back(Part::Sphere({0, 0, 0}, 0.7f * s));
        c.bottom_y_m = 0.7f * s;
        break;
      default:  // a can: tall and narrow
        c.shape.parts.push_back(Part::Box({0, 0, 0}, {0.6f * s, 2.0f * s, 0.6f * s}));
        c.bottom_y_m = 2.0f * s;
    }
    out.push_back(c);
  }
  return out;
}

}  // namespace

Eigen::Vector2f Trajectory::PositionAt(double t) const {
  switch (kind) {
    case Kind::kStatic:
      return start_xz_m;
    case Kind::kLinear:
      return start_xz_m + velocity_xz_mps * static_cast<float>(t);
    case Kind::kCircular: {
      const double a = kTwoPi * t / period_s;
      return centre_xz_m + radius_m * Eigen::Vector2f(std::cos(a), std::sin(a));
    }
    case Kind::kLeaveReturn: {
      const double half = period_s / 2, phase = std::fmod(t, static_cast<double>(period_s));
      const double s = phase < half ? phase : period_s - phase;
      return start_xz_m + velocity_xz_mps * static_cast<float>(s);
    }
  }
  return start_xz_m;
}

Eigen::Isometry3f PlanarPose(const Trajectory& motion, double t) {
  const Eigen::Vector2f xz = motion.PositionAt(t);
  Eigen::Isometry3f X = Eigen::Isometry3f::Identity();
  X.linear() = Eigen::AngleAxisf(motion.YawAt(t), Eigen::Vector3f::UnitY()).toRotationMatrix();
  X.translation() = Eigen::Vector3f(xz.x(), 0.0f, xz.y());
  return X;
}

float Trajectory::YawAt(double t) const { return yaw_rad + yaw_rate_radps * static_cast<float>(t); }

bool Scenario::IsValid(std::string* error) const {
  if (frames < 1 || frames > kMaxSequenceFrames)
    return Fail(error, "frames must be 1-" + std::to_string(kMaxSequenceFrames));
  if (!(rate_hz >= 0.01 && rate_hz <= 1000)) return Fail(error, "rate_hz must be 0.01-1000 Hz");
  if (!(table_height_m > 0) || !std::isfinite(table_height_m))
    return Fail(error, "table_height_m must be > 0");
  if (target.parts.empty()) return Fail(error, "target has no part");
  // Within a room's reach: a value far beyond any sensor's range (a typo, a crafted file) would
  // put objects where no pixel can see them, or at infinity.
  constexpr float kReach = 100;  // metres, metres a second, radians (a second)
  const auto within = [&](float v) { return std::isfinite(v) && std::abs(v) <= kReach; };
  const auto shown = [](float v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  if (!within(table_height_m) || !within(target_bottom_y_m))
    return Fail(error, "table_height_m and target_bottom_y_m must be within 100 m");
  for (const Trajectory* m : {&target_motion, &camera_motion}) {
    if (!(m->period_s > 0) || !std::isfinite(m->period_s))
      return Fail(error, "trajectory period_s must be > 0");
    for (const float v :
         {m->start_xz_m.x(), m->start_xz_m.y(), m->velocity_xz_mps.x(), m->velocity_xz_mps.y(),
          m->centre_xz_m.x(), m->centre_xz_m.y(), m->radius_m, m->yaw_rad, m->yaw_rate_radps})
      if (!within(v))
        return Fail(error,
                    "a trajectory's positions, speeds, radius and angles must be within 100 (m, "
                    "m/s, rad), got " +
                        shown(v));
  }
  for (const auto& c : clutter)
    for (const float v : {c.xz_m.x(), c.xz_m.y(), c.yaw_rad, c.bottom_y_m})
      if (!within(v)) return Fail(error, "clutter must stand within 100 m, got " + shown(v));
  if (occluded_frames < 0) return Fail(error, "occluded_frames must be >= 0");
  return true;
}

Eigen::Vector3f ShapeCentre(const Shape& shape) {
  Box b{Eigen::Vector3f::Constant(1e9f), Eigen::Vector3f::Constant(-1e9f)};
  for (const auto& p : shape.parts) {
    const Eigen::Vector3f half =
        p.kind == Shape::Part::Kind::kBox ? p.half_size_m : Eigen::Vector3f::Constant(p.radius_m);
    b.min = b.min.cwiseMin(p.centre_m - half);
    b.max = b.max.cwiseMax(p.centre_m + half);
  }
  return (b.min + b.max) / 2;
}

Eigen::Isometry3f ScenarioTargetPose(const Scenario& sc, int index) {
  const double t = index / sc.rate_hz;
  const Eigen::Vector2f xz = sc.target_motion.PositionAt(t);
  return PlanarPose(sc.camera_motion, t).inverse() *
         PoseOnTable(xz.x(), xz.y(), sc.target_motion.YawAt(t), sc.table_height_m,
                     sc.target_bottom_y_m);
}

ScenarioFrame RenderScenarioFrame(const Scenario& sc, int index, const CameraIntrinsics& k) {
  ScenarioFrame out;
  out.time_s = index / sc.rate_hz;
  const Eigen::Isometry3f X_CW = PlanarPose(sc.camera_motion, out.time_s).inverse();
  const Eigen::Isometry3f X_CO = ScenarioTargetPose(sc, index);
  std::vector<SceneObject> objects = {{sc.target, X_CO, kTargetLabel}};
  std::size_t shown = sc.clutter.size();
  if (sc.clutter_grows) shown = std::min<std::size_t>(index, sc.clutter.size());
  for (std::size_t i = 0; i < shown; ++i) {
    const auto& c = sc.clutter[i];
    objects.push_back(
        {c.shape,
         X_CW * PoseOnTable(c.xz_m.x(), c.xz_m.y(), c.yaw_rad, sc.table_height_m, c.bottom_y_m),
         static_cast<std::uint32_t>(i + 2)});
  }
  out.truth.target_pose = X_CO;
  out.truth.centroid_m = X_CO * ShapeCentre(sc.target);
  if (index >= sc.occluded_from && index < sc.occluded_from + sc.occluded_frames) {
    // The screen stands on the table 35% of the way from the camera to the target, facing it.
    const Eigen::Vector3f c = out.truth.centroid_m * 0.65f;
    const float facing = std::atan2(c.x(), c.z());
    objects.push_back(
        {ScreenShape(), PoseOnTable(c.x(), c.z(), facing, sc.table_height_m, 0.2f), 1000});
  }
  // One seed per frame: the same frame renders the same every time.
  const std::uint32_t seed = sc.seed * 7919u + static_cast<std::uint32_t>(index);
  out.rendered = RenderScene(objects, sc.table_height_m, k, sc.noise, seed);
  // The target alone, counted over its own pixels only: what of it the sensor would see
  // unoccluded, were the image not cut at its edges (a sliver at the edge is not the object in
  // view: the image is widened by its own size on every side).
  CameraIntrinsics unbounded = k;
  unbounded.width = 3 * k.width, unbounded.height = 3 * k.height;
  unbounded.cx += k.width, unbounded.cy += k.height;
  const std::size_t whole =
      CountReturns({objects.front()}, sc.table_height_m, unbounded, sc.noise, kTargetLabel);
  const auto seen = std::count(out.rendered.label.begin(), out.rendered.label.end(), kTargetLabel);
  out.truth.visible_fraction =
      whole > 0 ? static_cast<float>(seen) / static_cast<float>(whole) : 0.0f;
  return out;
}

std::vector<std::string> ScenarioPresetNames() {
  return {"static", "linear", "circular", "occluded", "leave-return", "paper-protocol"};
}

std::optional<Scenario> ScenarioPreset(const std::string& name) {
  Scenario s;
  s.name = name;
  s.clutter = DemoClutter();
  s.target_motion.start_xz_m = {0.0f, 1.0f};
  s.target_motion.yaw_rad = 0.3f;
  using Kind = Trajectory::Kind;
  if (name == "static") {
    s.frames = 30;
  } else if (name == "linear") {  // 30 cm to the right in 3 s, turning slowly
    s.target_motion.kind = Kind::kLinear;
    s.target_motion.start_xz_m = {-0.15f, 1.0f};
    s.target_motion.velocity_xz_mps = {0.1f, 0.0f};
    s.target_motion.yaw_rate_radps = 0.05f;
  } else if (name == "circular") {  // a 20 cm circle in 6 s
    s.frames = 180;
    s.target_motion.kind = Kind::kCircular;
    s.target_motion.centre_xz_m = {0.0f, 1.05f};
    s.target_motion.radius_m = 0.2f;
    s.target_motion.period_s = 6.0f;
  } else if (name == "occluded") {  // hidden behind a screen for half a second
    s.frames = 60;
    s.occluded_from = 20;
    s.occluded_frames = 15;
  } else if (name == "leave-return") {  // out of the right edge of the view and back, in 4 s
    s.frames = 120;
    s.target_motion.kind = Kind::kLeaveReturn;
    s.target_motion.start_xz_m = {0.1f, 1.0f};
    s.target_motion.velocity_xz_mps = {0.5f, 0.0f};
    s.target_motion.period_s = 4.0f;
  } else if (name == "paper-protocol") {  // 12 scenes of a ball among growing clutter
    s.frames = 12;
    s.rate_hz = 1.0;
    s.target = Shape{{Shape::Part::Sphere({0, 0, 0}, 0.08f)}};
    s.target_bottom_y_m = 0.08f;
    s.target_motion.start_xz_m = {0.05f, 1.1f};
    s.clutter = ProtocolClutter(s.seed, s.target_motion.start_xz_m);
    s.clutter_grows = true;
  } else {
    return std::nullopt;
  }
  return s;
}

Cloud CaptureTargetModel(Scenario capture, std::uint32_t seed, const CameraIntrinsics& intrinsics) {
  capture.seed = seed;
  capture.clutter.clear();  // the model is made from the target alone
  capture.occluded_frames = 0;
  const ScenarioFrame frame = RenderScenarioFrame(capture, 0, intrinsics);
  return CutModel(frame.rendered, kTargetLabel, frame.truth.target_pose);
}

Cloud SyntheticTargetModel(std::uint32_t seed, const CameraIntrinsics& intrinsics) {
  Scenario capture = *ScenarioPreset("static");
  capture.target_motion.start_xz_m = {0.0f, 0.9f};
  capture.target_motion.yaw_rad = 0.35f;
  return CaptureTargetModel(capture, seed, intrinsics);
}

Cloud SyntheticBallModel(std::uint32_t seed, const CameraIntrinsics& intrinsics) {
  Scenario capture = *ScenarioPreset("paper-protocol");
  capture.target_motion.start_xz_m = {0.0f, 0.9f};
  return CaptureTargetModel(capture, seed, intrinsics);
}

CrossCaptureCase MakeDemoCase(std::uint32_t seed, const CameraIntrinsics& intrinsics) {
  Scenario scene = *ScenarioPreset("static");
  scene.seed = seed + 1;
  scene.target_motion.start_xz_m = {0.05f, 0.95f};
  scene.target_motion.yaw_rad = 0.45f;

  ScenarioFrame scene_frame = RenderScenarioFrame(scene, 0, intrinsics);
  CrossCaptureCase c;
  c.model = SyntheticTargetModel(seed, intrinsics);
  c.scene = std::move(scene_frame.rendered);
  c.truth = scene_frame.truth.target_pose;
  c.clutter_objects = static_cast<int>(scene.clutter.size());
  return c;
}

}  // namespace saccade
