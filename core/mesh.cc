#include "core/mesh.h"

#include "core/fail.h"
#include "core/surface_views.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace saccade {

bool IsValidMesh(const Mesh& mesh, std::string* error) {
  if (mesh.triangles.empty()) return Fail(error, "the mesh has no faces");
  const int n = int(mesh.vertices.size());
  bool some_area = false;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int i : mesh.triangles[t])
      if (i < 0 || i >= n)
        return Fail(error, "face " + std::to_string(t + 1) + " names vertex " +
                               std::to_string(i + 1) + " of " + std::to_string(n));
    const auto& [a, b, c] = mesh.triangles[t];
    const Eigen::Vector3f& A = mesh.vertices[std::size_t(a)];
    if (!A.allFinite() || !mesh.vertices[std::size_t(b)].allFinite() ||
        !mesh.vertices[std::size_t(c)].allFinite())
      return Fail(error, "face " + std::to_string(t + 1) + " has a vertex that is not a number");
    some_area |=
        (mesh.vertices[std::size_t(b)] - A).cross(mesh.vertices[std::size_t(c)] - A).norm() > 0;
  }
  if (!some_area) return Fail(error, "every face of the mesh has zero area");
  if (!mesh.vertex_colours.empty() && mesh.vertex_colours.size() != mesh.vertices.size())
    return Fail(error, "the mesh has colours for some of its vertices only");
  if (!mesh.face_colours.empty() && mesh.face_colours.size() != mesh.triangles.size())
    return Fail(error, "the mesh has colours for some of its faces only");
  return true;
}

bool MeshViewOptions::IsValid(std::string* error) const {
  if (views < 1 || views > 10000) return Fail(error, "views must be in [1, 10000]");
  if (!(std::isfinite(distance_m) && distance_m > 0)) return Fail(error, "distance must be > 0");
  if (!(std::isfinite(spacing_m) && spacing_m > 0)) return Fail(error, "spacing must be > 0");
  return true;
}

MeshDepth RenderMeshDepth(const Mesh& mesh, const CameraIntrinsics& k,
                          const Eigen::Matrix4f& camera_to_mesh) {
  MeshDepth out;
  out.width = k.width, out.height = k.height;
  out.depth.assign(std::size_t(k.width) * std::size_t(k.height),
                   std::numeric_limits<float>::quiet_NaN());
  out.triangle.assign(out.depth.size(), -1);
  const Eigen::Matrix4f mesh_to_camera = camera_to_mesh.inverse();
  std::vector<Eigen::Vector3f> cam(mesh.vertices.size());
  for (std::size_t i = 0; i < cam.size(); ++i)
    cam[i] = (mesh_to_camera * mesh.vertices[i].homogeneous()).head<3>();
  constexpr float kNear = 0.01f;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    Eigen::Vector3f p[3];
    Eigen::Vector2f uv[3];
    bool behind = false;
    for (int j = 0; j < 3; ++j) {
      p[j] = cam[std::size_t(tri[std::size_t(j)])];
      behind |= p[j].z() < kNear;
      if (!behind) uv[j] = k.Project(p[j]).cast<float>();
    }
    if (behind) continue;  // the views stand well outside the mesh: nothing is cut by the plane
    const auto edge = [](const Eigen::Vector2f& a, const Eigen::Vector2f& b, float x, float y) {
      return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
    };
    const float area = edge(uv[0], uv[1], uv[2].x(), uv[2].y());
    if (std::abs(area) < 1e-9f) continue;  // seen edge-on
    const int u0 = std::max(0, int(std::ceil(std::min({uv[0].x(), uv[1].x(), uv[2].x()}))));
    const int u1 =
        std::min(k.width - 1, int(std::floor(std::max({uv[0].x(), uv[1].x(), uv[2].x()}))));
    const int v0 = std::max(0, int(std::ceil(std::min({uv[0].y(), uv[1].y(), uv[2].y()}))));
    const int v1 =
        std::min(k.height - 1, int(std::floor(std::max({uv[0].y(), uv[1].y(), uv[2].y()}))));
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        // Barycentric weights in the image, then depth interpolated in 1/z (perspective).
        const float w0 = edge(uv[1], uv[2], float(u), float(v)) / area;
        const float w1 = edge(uv[2], uv[0], float(u), float(v)) / area;
        const float w2 = 1 - w0 - w1;
        constexpr float kEps = -1e-5f;
        if (w0 < kEps || w1 < kEps || w2 < kEps) continue;
        const float z = 1 / (w0 / p[0].z() + w1 / p[1].z() + w2 / p[2].z());
        const std::size_t i = std::size_t(v) * std::size_t(k.width) + std::size_t(u);
        if (!(z >= out.depth[i])) {  // NaN (empty) or farther
          out.depth[i] = z;
          out.triangle[i] = int(t);
        }
      }
  }
  return out;
}

namespace {

// The colour of `mesh` at point `p` on triangle `t`: the face's, or its vertices' blended by
// where p lies; grey when the mesh has none.
std::array<std::uint8_t, 3> ColourAt(const Mesh& mesh, int t, const Eigen::Vector3f& p) {
  if (!mesh.face_colours.empty()) return mesh.face_colours[std::size_t(t)];
  if (mesh.vertex_colours.empty()) return {160, 160, 160};
  const auto& tri = mesh.triangles[std::size_t(t)];
  const Eigen::Vector3f a = mesh.vertices[std::size_t(tri[0])],
                        b = mesh.vertices[std::size_t(tri[1])],
                        c = mesh.vertices[std::size_t(tri[2])];
  const Eigen::Vector3f n = (b - a).cross(c - a);
  const float n2 = std::max(1e-20f, n.squaredNorm());
  const float wa = std::clamp((c - b).cross(p - b).dot(n) / n2, 0.0f, 1.0f);
  const float wb = std::clamp((a - c).cross(p - c).dot(n) / n2, 0.0f, 1.0f);
  const float wc = std::max(0.0f, 1 - wa - wb);
  std::array<std::uint8_t, 3> out{};
  for (std::size_t ch = 0; ch < 3; ++ch)
    out[ch] =
        std::uint8_t(std::lround(std::clamp(wa * mesh.vertex_colours[std::size_t(tri[0])][ch] +
                                                wb * mesh.vertex_colours[std::size_t(tri[1])][ch] +
                                                wc * mesh.vertex_colours[std::size_t(tri[2])][ch],
                                            0.0f, 255.0f)));
  return out;
}

}  // namespace

MeshModel RenderMeshModel(const Mesh& mesh, const MeshViewOptions& options) {
  MeshModel out;
  Eigen::Vector3f lo = mesh.vertices.front(), hi = lo;
  for (const Eigen::Vector3f& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Eigen::Vector3f centre = (lo + hi) / 2;
  const float radius = (hi - lo).norm() / 2;
  const CameraIntrinsics& k = options.intrinsics;
  const float distance = ViewDistance(radius, k, options.distance_m);
  std::vector<Eigen::Vector3f> face_normal(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3f& a = mesh.vertices[std::size_t(tri[0])];
    face_normal[t] = (mesh.vertices[std::size_t(tri[1])] - a)
                         .cross(mesh.vertices[std::size_t(tri[2])] - a)
                         .normalized();
  }
  // One point per cube of spacing_m, the first view to see it giving it.
  std::unordered_map<std::int64_t, int> kept;
  const auto key = [&](const Eigen::Vector3f& p) {
    // Cells offset by a fraction of a spacing: a face at the mesh's bounds lies inside a cell, not
    // on a boundary its rendering noise would straddle.
    const Eigen::Vector3f q = (p - lo) / options.spacing_m + Eigen::Vector3f::Constant(0.37f);
    return (std::int64_t(q.x()) * 1000003 + std::int64_t(q.y())) * 1000003 + std::int64_t(q.z());
  };
  for (const Eigen::Vector3f& dir : SphereDirections(options.views)) {
    const Eigen::Vector3f eye = centre + distance * dir;
    const Eigen::Matrix4f pose = LookAt(eye, centre);
    const MeshDepth view = RenderMeshDepth(mesh, k, pose);
    int seen = 0;
    for (int v = 0; v < view.height; ++v)
      for (int u = 0; u < view.width; ++u) {
        const std::size_t i = std::size_t(v) * std::size_t(view.width) + std::size_t(u);
        if (view.triangle[i] < 0) continue;
        ++seen;
        const Eigen::Vector3f p = (pose * k.Unproject(u, v, view.depth[i]).homogeneous()).head<3>();
        if (!kept.emplace(key(p), int(out.points.size())).second) continue;
        Eigen::Vector3f n = face_normal[std::size_t(view.triangle[i])];
        if (n.dot(eye - p) < 0) n = -n;  // towards the side this view saw
        PointT q;
        q.getVector3fMap() = p;
        const auto rgb = ColourAt(mesh, view.triangle[i], p);
        q.r = rgb[0], q.g = rgb[1], q.b = rgb[2], q.a = 255;
        out.points.push_back(q);
        out.normals.push_back(n);
      }
    out.viewpoints.push_back(eye);
    out.points_per_view.push_back(seen);
  }
  out.points.width = std::uint32_t(out.points.size());
  out.points.height = 1;
  out.points.is_dense = true;
  // No camera saw it from one place: the sensor origin is set inside it, at its centre, which
  // is how a model tells it holds a whole surface (DescribeModel), in the PCD's VIEWPOINT.
  out.points.sensor_origin_ = centre.homogeneous();
  return out;
}

}  // namespace saccade
