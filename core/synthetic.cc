#include "core/synthetic.h"

#include <cmath>
#include <limits>
#include <random>

namespace saccade {

Shape TargetShape() {
  // Curved parts of three sizes on a flat slab: the creases where they meet give local frames
  // that repeat from view to view, which flat faces or a lone sphere would not.
  using Part = Shape::Part;
  Shape s;
  s.parts.push_back(Part::Sphere({0, 0, 0}, 0.05f));
  s.parts.push_back(Part::Sphere({0.05f, -0.03f, 0.01f}, 0.035f));
  s.parts.push_back(Part::Sphere({-0.045f, -0.04f, -0.02f}, 0.028f));
  s.parts.push_back(Part::Sphere({0.0f, -0.075f, 0.02f}, 0.022f));
  s.parts.push_back(Part::Box({0.0f, 0.03f, 0.0f}, {0.07f, 0.02f, 0.05f}));
  return s;
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Nearest hit of ray o + t d (t > 0) with a part, in the part's object frame; outputs normal.
float Intersect(const Shape::Part& p, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                Eigen::Vector3f* normal) {
  if (p.kind == Shape::Part::Kind::kSphere) {
    const Eigen::Vector3f oc = o - p.centre_m;
    const float b = oc.dot(d), c = oc.squaredNorm() - p.radius_m * p.radius_m;
    const float disc = b * b - c;
    if (disc < 0) return kInf;
    const float t = -b - std::sqrt(disc);
    if (t <= 0) return kInf;
    *normal = (o + t * d - p.centre_m).normalized();
    return t;
  }
  float t0 = -kInf, t1 = kInf;
  int axis = -1;
  float sign = 1;
  for (int a = 0; a < 3; ++a) {
    const float lo = p.centre_m[a] - p.half_size_m[a], hi = p.centre_m[a] + p.half_size_m[a];
    if (std::abs(d[a]) < 1e-12f) {
      if (o[a] < lo || o[a] > hi) return kInf;
      continue;
    }
    float ta = (lo - o[a]) / d[a], tb = (hi - o[a]) / d[a];
    float s = -1;
    if (ta > tb) std::swap(ta, tb), s = 1;
    if (ta > t0) t0 = ta, axis = a, sign = s;
    t1 = std::min(t1, tb);
  }
  if (t0 > t1 || t0 <= 0 || axis < 0) return kInf;
  normal->setZero();
  (*normal)[axis] = sign;
  return t0;
}

// An object as the renderer sees it: rays move into its frame by X_OC, and a sphere in that
// frame bounds all its parts, so most rays skip most objects after one test.
struct Placed {
  const SceneObject* object = nullptr;
  Eigen::Isometry3f X_OC = Eigen::Isometry3f::Identity();
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();  // bounding sphere, object frame
  float radius = 0;

  explicit Placed(const SceneObject& o) : object(&o), X_OC(o.pose.inverse()) {
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(kInf), hi = -lo;
    for (const auto& p : o.shape.parts) {
      const Eigen::Vector3f half = p.kind == Shape::Part::Kind::kBox
                                       ? p.half_size_m
                                       : Eigen::Vector3f::Constant(p.radius_m);
      lo = lo.cwiseMin(p.centre_m - half);
      hi = hi.cwiseMax(p.centre_m + half);
    }
    if (o.shape.parts.empty()) return;
    centre = (lo + hi) / 2;
    radius = (hi - lo).norm() / 2 * 1.0001f + 1e-6f;
  }

  /// False when the ray o + t d (object frame, |d| = 1) cannot hit a part at 0 < t < max_t.
  bool MayHit(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float max_t) const {
    const Eigen::Vector3f oc = centre - o;
    const float tc = oc.dot(d);
    const float off2 = oc.squaredNorm() - tc * tc;
    const float r2 = radius * radius;
    if (off2 > r2) return false;
    const float half_chord = std::sqrt(r2 - off2);
    return tc + half_chord > 0 && tc - half_chord < max_t;
  }
};

// True when something lies between the projector and `point` (both in the camera frame).
bool Shadowed(const std::vector<Placed>& placed, float table_height_m,
              const Eigen::Vector3f& point, const Eigen::Vector3f& projector) {
  const Eigen::Vector3f to_point = point - projector;
  const float distance = to_point.norm();
  const Eigen::Vector3f d = to_point / distance;
  const float reach = distance - 0.002f;  // the surface itself does not shadow its own point
  if (d.y() > 1e-6f && table_height_m - projector.y() < reach * d.y()) return true;
  for (const Placed& p : placed) {
    const Eigen::Vector3f o = p.X_OC * projector;
    const Eigen::Vector3f dl = p.X_OC.linear() * d;
    if (!p.MayHit(o, dl, reach)) continue;
    Eigen::Vector3f n;
    for (const auto& part : p.object->shape.parts)
      if (Intersect(part, o, dl, &n) < reach) return true;
  }
  return false;
}

}  // namespace

RenderedFrame RenderScene(const std::vector<SceneObject>& objects, float table_height_m,
                          const CameraIntrinsics& k, const KinectNoise& noise, std::uint32_t seed) {
  RenderedFrame f;
  f.cloud.width = static_cast<std::uint32_t>(k.width);
  f.cloud.height = static_cast<std::uint32_t>(k.height);
  f.cloud.is_dense = false;
  f.cloud.resize(static_cast<std::size_t>(k.width) * k.height);
  f.label.assign(f.cloud.size(), 0);
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  // Rays in each object's frame are the camera rays moved by X_OC.
  std::vector<Placed> placed;
  for (const auto& o : objects) placed.emplace_back(o);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3f ray(static_cast<float>((u - k.cx) / k.fx),
                                static_cast<float>((v - k.cy) / k.fy), 1.0f);
      const Eigen::Vector3f d = ray.normalized();
      float best = kInf;
      Eigen::Vector3f best_normal = -Eigen::Vector3f::UnitY();
      std::uint32_t best_label = 0;
      if (d.y() > 1e-6f) {  // the table plane, seen from above
        best = table_height_m / d.y();
        best_normal = -Eigen::Vector3f::UnitY();
      }
      for (std::size_t i = 0; i < objects.size(); ++i) {
        const Eigen::Vector3f o = placed[i].X_OC.translation();
        const Eigen::Vector3f dl = placed[i].X_OC.linear() * d;
        if (!placed[i].MayHit(o, dl, best)) continue;
        for (const auto& part : objects[i].shape.parts) {
          Eigen::Vector3f n;
          const float t = Intersect(part, o, dl, &n);
          if (t < best) {
            best = t;
            best_normal = objects[i].pose.linear() * n;
            best_label = objects[i].label;
          }
        }
      }
      auto& p = f.cloud[static_cast<std::size_t>(v) * k.width + u];
      p.x = p.y = p.z = nan;
      p.r = p.g = p.b = 128;
      p.a = 255;
      if (!std::isfinite(best)) continue;
      double z = best * d.z();
      const double incidence = std::abs(best_normal.dot(d));
      // Draw the noise for every pixel, so a pixel's noise does not depend on its neighbours.
      const double n1 = gauss(rng);
      if (z < noise.min_range_m || z > noise.max_range_m) continue;
      if (noise.enabled) {
        if (incidence < noise.grazing_cos) continue;
        if (noise.projector_shadows &&
            Shadowed(placed, table_height_m, best * d,
                     Eigen::Vector3f(static_cast<float>(noise.baseline_m), 0, 0)))
          continue;
        z += noise.sigma_at_1m_m * z * z * n1;
        // Disparity quantization: the Kinect measures disparity in 1/8 pixel steps.
        const double disparity = k.fx * noise.baseline_m / z;
        const double q = std::round(disparity / noise.disparity_step) * noise.disparity_step;
        z = k.fx * noise.baseline_m / q;
      }
      p.z = static_cast<float>(z);
      p.x = static_cast<float>((u - k.cx) * z / k.fx);
      p.y = static_cast<float>((v - k.cy) * z / k.fy);
      f.label[static_cast<std::size_t>(v) * k.width + u] = best_label;
      if (best_label) p.r = 200, p.g = 60, p.b = 40;
    }
  }
  return f;
}

Cloud CutModel(const RenderedFrame& frame, std::uint32_t label, const Eigen::Isometry3f& X_CO) {
  const Eigen::Isometry3f X_OC = X_CO.inverse();
  Cloud model;
  for (std::size_t i = 0; i < frame.cloud.size(); ++i) {
    if (frame.label[i] != label || !std::isfinite(frame.cloud[i].z)) continue;
    PointT p = frame.cloud[i];
    p.getVector3fMap() = X_OC * p.getVector3fMap();
    model.push_back(p);
  }
  model.width = static_cast<std::uint32_t>(model.size());
  model.height = 1;
  // Where the camera was, in the object's frame: normals are oriented towards it.
  model.sensor_origin_.head<3>() = X_OC.translation();
  model.sensor_orientation_ = Eigen::Quaternionf(X_OC.linear());
  return model;
}

Eigen::Isometry3f PoseOnTable(float x_m, float z_m, float yaw_rad, float table_height_m,
                              float bottom_y_m) {
  Eigen::Isometry3f X = Eigen::Isometry3f::Identity();
  X.linear() = Eigen::AngleAxisf(yaw_rad, Eigen::Vector3f::UnitY()).toRotationMatrix();
  X.translation() = Eigen::Vector3f(x_m, table_height_m - bottom_y_m, z_m);
  return X;
}

}  // namespace saccade
