#include "core/tracking.h"

#include "core/check.h"
#include "core/fail.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <optional>

namespace saccade {
namespace {

// The rotation's damping, a share of its mean curvature (TrackPose). make bench-track holds
// 1394-1408 of its 1482 visible frames within tolerance for any share from 1e-4 to 1
// (docs/BENCHMARKS.md): the gentlest that stops noise-driven spin is kept.
constexpr double kRotationDamping = 0.01;

// The point seen at pixel (u, v) and the frame's normal there (from the points `step` pixels
// around it, turned towards the camera); nullopt where the pixel or its neighbours have no
// depth.
struct Seen {
  Eigen::Vector3f point;
  Eigen::Vector3f normal;
};
std::optional<Seen> SeenAt(const Cloud& frame, int u, int v, int step) {
  const int w = static_cast<int>(frame.width), h = static_cast<int>(frame.height);
  if (u - step < 0 || v - step < 0 || u + step >= w || v + step >= h) return std::nullopt;
  const auto at = [&](int x, int y) { return frame.at(x, y).getVector3fMap(); };
  const Eigen::Vector3f p = at(u, v), l = at(u - step, v), r = at(u + step, v), t = at(u, v - step),
                        b = at(u, v + step);
  if (!p.allFinite() || !l.allFinite() || !r.allFinite() || !t.allFinite() || !b.allFinite())
    return std::nullopt;
  Eigen::Vector3f n = (r - l).cross(b - t);
  const float norm = n.norm();
  if (!(norm > 0)) return std::nullopt;
  n /= norm;
  if (n.dot(p) > 0) n = -n;  // towards the camera at the origin
  return Seen{p, n};
}

// Where a model point lands: the pixel and what is seen there, or nullopt when it faces away,
// falls outside the image or meets no depth.
struct Pair {
  Eigen::Vector3f p;  // the model point in the camera frame
  Seen seen;
};
// A model point at p with normal n (camera frame) the camera sees the front of.
bool FacesCamera(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  return p.z() > 0.05f && n.allFinite() && n.dot(p) < 0;
}

// Whether pixel coordinates `uv` fall inside the image.
bool InsideImage(const CameraIntrinsics& k, const Eigen::Vector2d& uv) {
  return uv.x() > -0.5 && uv.y() > -0.5 && uv.x() < k.width - 0.5 && uv.y() < k.height - 0.5;
}

// Where a model point stands for the in-image share (InImageShare): facing the camera, and
// then inside the image.
struct InView {
  int facing = 0, inside = 0;
  float Share() const { return facing > 0 ? float(inside) / float(facing) : 1.0f; }
};

// Model point i at X_CM, in the camera frame, when it faces the camera; `in_view`, when given,
// counts it and whether it lands inside the image. Its pixel in `uv`.
std::optional<Eigen::Vector3f> FacingPoint(const VerificationModel& model, std::size_t i,
                                           const CameraIntrinsics& k, const Eigen::Isometry3f& X_CM,
                                           Eigen::Vector2d* uv, InView* in_view) {
  const Eigen::Vector3f p = X_CM * model.points[i].getVector3fMap();
  const Eigen::Vector3f n = X_CM.linear() * model.normals[i];
  if (!FacesCamera(p, n)) return std::nullopt;
  *uv = k.Project(p);
  if (in_view) {
    ++in_view->facing;
    in_view->inside += InsideImage(k, *uv);
  }
  return p;
}

// `in_view`, when given, counts the point (PairOf's pass doubles as InImageShare's).
std::optional<Pair> PairOf(const VerificationModel& model, std::size_t i, const Cloud& frame,
                           const CameraIntrinsics& k, const Eigen::Isometry3f& X_CM,
                           int normal_step_px, InView* in_view = nullptr) {
  Eigen::Vector2d uv;
  const std::optional<Eigen::Vector3f> p = FacingPoint(model, i, k, X_CM, &uv, in_view);
  if (!p) return std::nullopt;
  const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
  const std::optional<Seen> seen = SeenAt(frame, u, v, normal_step_px);
  if (!seen) return std::nullopt;
  return Pair{*p, *seen};
}

// The share of the model's points facing the camera at X_CM that project inside the image (1
// when none faces it).
float InImageShare(const VerificationModel& model, const CameraIntrinsics& k,
                   const Eigen::Isometry3f& X_CM) {
  InView in_view;
  Eigen::Vector2d uv;
  for (std::size_t i = 0; i < model.points.size(); ++i)
    FacingPoint(model, i, k, X_CM, &uv, &in_view);
  return in_view.Share();
}

// The score of pose X_CM (its facing, inliers, free space, fitness, coverage, residual).
TrackResult Score(const VerificationModel& model, const Cloud& frame, const CameraIntrinsics& k,
                  const Eigen::Isometry3f& X_CM, const TrackOptions& o) {
  TrackResult result;
  double sq = 0;
  InView in_view;
  for (std::size_t i = 0; i < model.points.size(); ++i) {
    const std::optional<Pair> pr = PairOf(model, i, frame, k, X_CM, o.normal_step_px, &in_view);
    if (!pr) continue;
    ++result.facing;
    const float distance = (pr->p - pr->seen.point).norm();
    if (distance <= o.inlier_distance_m) {
      ++result.inliers;
      const double e = pr->seen.normal.dot(pr->p - pr->seen.point);
      sq += e * e;
    } else if (pr->p.z() <= pr->seen.point.z() - o.free_space_margin_m) {
      ++result.free_space;
    }
  }
  result.model_to_camera = X_CM.matrix();
  result.in_image = in_view.Share();
  if (result.inliers + result.free_space > 0)
    result.fitness = float(result.inliers) / float(result.inliers + result.free_space);
  if (result.facing > 0) result.coverage = float(result.inliers) / float(result.facing);
  if (result.inliers > 0) result.rms_m = float(std::sqrt(sq / result.inliers));
  result.tracking = result.fitness >= o.min_fitness && result.coverage >= o.min_coverage;
  return result;
}

void CheckFrame(const Cloud& frame, const CameraIntrinsics& k, const TrackOptions& o) {
  SACCADE_CHECK_VALID(o);
  SACCADE_CHECK(frame.height > 1 && static_cast<int>(frame.width) == k.width &&
                    static_cast<int>(frame.height) == k.height,
                "an organized frame of the intrinsics' size");
}

}  // namespace

bool TrackOptions::IsValid(std::string* error) const {
  if (iterations < 1) return Fail(error, "iterations must be >= 1");
  if (!(max_distance_m > 0)) return Fail(error, "max_distance_m must be > 0");
  if (!(inlier_distance_m > 0)) return Fail(error, "inlier_distance_m must be > 0");
  if (!(free_space_margin_m > 0)) return Fail(error, "free_space_margin_m must be > 0");
  if (!(min_fitness >= 0 && min_fitness <= 1)) return Fail(error, "min_fitness must be in [0, 1]");
  if (!(min_coverage >= 0 && min_coverage <= 1))
    return Fail(error, "min_coverage must be in [0, 1]");
  if (normal_step_px < 1) return Fail(error, "normal_step_px must be >= 1");
  if (!(min_in_image_to_turn >= 0 && min_in_image_to_turn <= 1))
    return Fail(error, "min_in_image_to_turn must be in [0, 1]");
  return true;
}

TrackResult TrackPose(const VerificationModel& model, const Cloud& frame, const CameraIntrinsics& k,
                      const Eigen::Matrix4f& predicted, const TrackOptions& o) {
  CheckFrame(frame, k, o);
  Eigen::Isometry3f X_CM(predicted);
  const auto pair_of = [&](std::size_t i) {
    return PairOf(model, i, frame, k, X_CM, o.normal_step_px);
  };

  // Rotations are taken about the model's centroid, where a turn of the object is one
  // direction of the step rather than a turn about the camera coupled with a slide.
  Eigen::Vector3d centre_M = Eigen::Vector3d::Zero();
  for (const PointT& p : model.points) centre_M += p.getVector3fMap().cast<double>();
  centre_M /= double(std::max<std::size_t>(1, model.points.size()));

  const bool hold_turn = InImageShare(model, k, X_CM) < o.min_in_image_to_turn;
  int iterations = 0;
  for (int it = 0; it < o.iterations; ++it) {
    // Gauss-Newton on the point-to-plane residuals n . (p - q), small motion [w, t] about the
    // centroid c: p' = p + w x (p - c) + t.
    const Eigen::Vector3d c = X_CM.cast<double>() * centre_M;
    Eigen::Matrix<double, 6, 6> JtJ = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> Jte = Eigen::Matrix<double, 6, 1>::Zero();
    int used = 0;
    for (std::size_t i = 0; i < model.points.size(); ++i) {
      const std::optional<Pair> pr = pair_of(i);
      if (!pr || (pr->p - pr->seen.point).norm() > o.max_distance_m) continue;
      const Eigen::Vector3d p = pr->p.cast<double>(), q = pr->seen.point.cast<double>(),
                            n = pr->seen.normal.cast<double>();
      Eigen::Matrix<double, 6, 1> J;
      J << (p - c).cross(n), n;
      const double e = n.dot(p - q);
      JtJ += J * J.transpose();
      Jte += J * e;
      ++used;
    }
    iterations = it + 1;
    if (used < 6) break;
    // Damping (Levenberg's), towards the current estimate, a share of each block's mean curvature:
    // a motion the surface does not constrain (a can's turn about its own axis, a plane's slide
    // along itself) has a near-zero pivot and would otherwise take whatever the noise gives it,
    // spinning the pose about the can instead of following it; the constrained ones are slowed
    // by about that share per step.
    const double rotation = JtJ.diagonal().head<3>().sum() / 3,
                 translation = JtJ.diagonal().tail<3>().sum() / 3;
    JtJ.diagonal().head<3>().array() += kRotationDamping * rotation;
    JtJ.diagonal().tail<3>().array() += 1e-4 * translation;
    Eigen::Matrix<double, 6, 1> x = Eigen::Matrix<double, 6, 1>::Zero();
    if (hold_turn)
      x.tail<3>() = JtJ.bottomRightCorner<3, 3>().ldlt().solve(-Jte.tail<3>());
    else
      x = JtJ.ldlt().solve(-Jte);
    if (!x.allFinite()) break;
    const Eigen::Vector3d w = x.head<3>();
    Eigen::Matrix3d turn = Eigen::Matrix3d::Identity();
    if (w.norm() > 0) turn = Eigen::AngleAxisd(w.norm(), w.normalized()).matrix();
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.linear() = turn;
    step.translation() = c + x.tail<3>() - turn * c;
    X_CM = Eigen::Isometry3f((step * X_CM.cast<double>()).cast<float>().matrix());
    if (x.head<3>().norm() < 1e-5 && x.tail<3>().norm() < 1e-5) break;  // converged
  }

  TrackResult result = Score(model, frame, k, X_CM, o);
  result.iterations = iterations;
  result.turn_held = hold_turn;
  return result;
}

TrackResult ScorePose(const VerificationModel& model, const Cloud& frame, const CameraIntrinsics& k,
                      const Eigen::Matrix4f& X_CM, const TrackOptions& o) {
  CheckFrame(frame, k, o);
  return Score(model, frame, k, Eigen::Isometry3f(X_CM), o);
}

}  // namespace saccade
