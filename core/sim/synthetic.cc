#include "core/sim/synthetic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace saccade {

Mesh ShapeMesh(const Shape& shape, int sphere_bands, const std::array<std::uint8_t, 3>& rgb) {
  Mesh mesh;
  const auto quad = [&](int a, int b, int c, int d) {
    mesh.triangles.push_back({a, b, c});
    mesh.triangles.push_back({a, c, d});
  };
  for (const Shape::Part& part : shape.parts) {
    const int base = int(mesh.vertices.size());
    if (part.kind == Shape::Part::Kind::kBox) {
      for (int i = 0; i < 8; ++i)  // corner i: bit 0 x, bit 1 y, bit 2 z (0 low, 1 high)
        mesh.vertices.push_back(part.centre_m +
                                part.half_size_m.cwiseProduct(Eigen::Vector3f(
                                    i & 1 ? 1.f : -1.f, i & 2 ? 1.f : -1.f, i & 4 ? 1.f : -1.f)));
      // Each face wound to face out.
      quad(base + 0, base + 2, base + 3, base + 1);  // z low
      quad(base + 4, base + 5, base + 7, base + 6);  // z high
      quad(base + 0, base + 1, base + 5, base + 4);  // y low
      quad(base + 2, base + 6, base + 7, base + 3);  // y high
      quad(base + 0, base + 4, base + 6, base + 2);  // x low
      quad(base + 1, base + 3, base + 7, base + 5);  // x high
      continue;
    }
    const int n = std::max(3, sphere_bands);
    for (int i = 0; i <= n; ++i) {  // latitude rings, pole to pole
      const double theta = M_PI * i / n;
      for (int j = 0; j < 2 * n; ++j) {
        const double phi = M_PI * j / n;
        mesh.vertices.push_back(part.centre_m +
                                part.radius_m *
                                    Eigen::Vector3f(float(std::sin(theta) * std::cos(phi)),
                                                    float(std::cos(theta)),
                                                    float(std::sin(theta) * std::sin(phi))));
      }
    }
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < 2 * n; ++j) {
        const int a = base + i * 2 * n + j, b = base + i * 2 * n + (j + 1) % (2 * n);
        quad(a, b, b + 2 * n, a + 2 * n);  // at the poles one of the two has no area
      }
  }
  mesh.face_colours.assign(mesh.triangles.size(), rgb);
  return mesh;
}

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
      const Eigen::Vector3f half =
          p.kind == Shape::Part::Kind::kBox ? p.half_size_m : Eigen::Vector3f::Constant(p.radius_m);
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
bool Shadowed(const std::vector<Placed>& placed, float table_height_m, const Eigen::Vector3f& point,
              const Eigen::Vector3f& projector) {
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

// What one pixel's ray meets first.
struct Hit {
  Eigen::Vector3f d = Eigen::Vector3f::Zero();  // unit ray direction, camera frame
  float t = kInf;                               // distance along it; kInf: nothing
  Eigen::Vector3f normal = -Eigen::Vector3f::UnitY();
  std::uint32_t label = 0;
};

Hit Cast(const std::vector<Placed>& placed, float table_height_m, const CameraIntrinsics& k, int u,
         int v) {
  Hit h;
  h.d = k.Unproject(u, v, 1.0).normalized();
  if (h.d.y() > 1e-6f) h.t = table_height_m / h.d.y();  // the table plane, seen from above
  for (const Placed& p : placed) {
    const Eigen::Vector3f o = p.X_OC.translation();
    const Eigen::Vector3f dl = p.X_OC.linear() * h.d;
    if (!p.MayHit(o, dl, h.t)) continue;
    for (const auto& part : p.object->shape.parts) {
      Eigen::Vector3f n;
      const float t = Intersect(part, o, dl, &n);
      if (t < h.t) {
        h.t = t;
        h.normal = p.object->pose.linear() * n;
        h.label = p.object->label;
      }
    }
  }
  return h;
}

// Whether the sensor returns a depth for a hit: in range, not at a grazing angle, lit by the
// projector. Geometry only: the noise moves depths, it never decides which pixels return.
bool Returns(const Hit& h, const std::vector<Placed>& placed, float table_height_m,
             const KinectNoise& noise) {
  const double z = h.t * h.d.z();
  if (z < noise.min_range_m || z > noise.max_range_m) return false;
  if (!noise.enabled) return true;
  if (std::abs(h.normal.dot(h.d)) < noise.grazing_cos) return false;
  return !(noise.projector_shadows &&
           Shadowed(placed, table_height_m, h.t * h.d,
                    Eigen::Vector3f(static_cast<float>(noise.baseline_m), 0, 0)));
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
  std::vector<Placed> placed;
  for (const auto& o : objects) placed.emplace_back(o);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const Hit h = Cast(placed, table_height_m, k, u, v);
      auto& p = f.cloud[static_cast<std::size_t>(v) * k.width + u];
      p.x = p.y = p.z = nan;
      p.r = p.g = p.b = 128;
      p.a = 255;
      if (!std::isfinite(h.t)) continue;
      // Draw the noise for every pixel, so a pixel's noise does not depend on its neighbours.
      const double n1 = gauss(rng);
      if (!Returns(h, placed, table_height_m, noise)) continue;
      double z = h.t * h.d.z();
      if (noise.enabled) {
        z += noise.sigma_at_1m_m * z * z * n1;
        // Disparity quantization: the Kinect measures disparity in 1/8 pixel steps.
        const double disparity = k.fx * noise.baseline_m / z;
        const double q = std::round(disparity / noise.disparity_step) * noise.disparity_step;
        z = k.fx * noise.baseline_m / q;
      }
      p.getVector3fMap() = k.Unproject(u, v, z);
      f.label[static_cast<std::size_t>(v) * k.width + u] = h.label;
      if (h.label) p.r = 200, p.g = 60, p.b = 40;
    }
  }
  return f;
}

std::size_t CountReturns(const std::vector<SceneObject>& objects, float table_height_m,
                         const CameraIntrinsics& k, const KinectNoise& noise, std::uint32_t label) {
  std::vector<Placed> placed;
  for (const auto& o : objects) placed.emplace_back(o);
  // Only the pixels onto which the labelled objects' bounding spheres project can hold them.
  int u0 = k.width, v0 = k.height, u1 = -1, v1 = -1;
  for (const Placed& p : placed) {
    if (p.object->label != label) continue;
    const Eigen::Vector3f c = p.object->pose * p.centre;
    if (!c.allFinite() || !std::isfinite(p.radius)) continue;  // nowhere a pixel can see
    const float near = c.z() - p.radius;
    if (near <= 1e-3f) {  // around or behind the camera: every pixel may see it
      u0 = v0 = 0, u1 = k.width - 1, v1 = k.height - 1;
      continue;
    }
    // The sphere's image lies within its centre's projection +- f R / (z - R).
    const double ru = k.fx * p.radius / near + 1, rv = k.fy * p.radius / near + 1;
    const Eigen::Vector2d uv = k.Project(c);
    const double cu = uv.x(), cv = uv.y();
    // Clamped to the image before the cast: a sphere far outside it (1e30 pixels off) is an
    // empty range, not an integer overflow.
    const auto pixel = [](double x, double size) { return int(std::clamp(x, -1.0, size)); };
    u0 = std::min(u0, pixel(std::floor(std::max(0.0, cu - ru)), k.width));
    v0 = std::min(v0, pixel(std::floor(std::max(0.0, cv - rv)), k.height));
    u1 = std::max(u1, pixel(std::ceil(std::min(k.width - 1.0, cu + ru)), k.width));
    v1 = std::max(v1, pixel(std::ceil(std::min(k.height - 1.0, cv + rv)), k.height));
  }
  std::size_t count = 0;
  for (int v = v0; v <= v1; ++v) {
    for (int u = u0; u <= u1; ++u) {
      const Hit h = Cast(placed, table_height_m, k, u, v);
      if (h.label == label && std::isfinite(h.t) && Returns(h, placed, table_height_m, noise))
        ++count;
    }
  }
  return count;
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
