#include "core/foveation.h"

#include "core/check.h"
#include "core/fail.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace saccade {
namespace {

bool AllFinite(const Eigen::Vector3f& v) { return v.allFinite(); }

std::string VecStr(const Eigen::Vector3f& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

}  // namespace

bool FoveaOptions::IsValid(std::string* error) const {
  if (finest_level < 1)
    return Fail(error, "finest_level must be >= 1 (two levels at least), got " +
                           std::to_string(finest_level));
  if (finest_level > 32)
    return Fail(error, "finest_level must be <= 32, got " + std::to_string(finest_level));
  if (!outer_box_from_scene) {
    if (!AllFinite(outer_size_m)) return Fail(error, "outer_size_m must be finite");
    if ((outer_size_m.array() <= 0).any())
      return Fail(error, "outer_size_m must be positive, got " + VecStr(outer_size_m));
    if (!AllFinite(outer_min_corner_m)) return Fail(error, "outer_min_corner_m must be finite");
    if (!outer_orientation.coeffs().allFinite() || outer_orientation.norm() < 1e-6f)
      return Fail(error, "outer_orientation must be a finite, non-zero quaternion");
    if ((inner_size_m.array() > outer_size_m.array()).any())
      return Fail(error, "inner_size_m " + VecStr(inner_size_m) +
                             " must not be larger than outer_size_m " + VecStr(outer_size_m));
  }
  if (!AllFinite(inner_size_m)) return Fail(error, "inner_size_m must be finite");
  if ((inner_size_m.array() <= 0).any())
    return Fail(error, "inner_size_m must be positive, got " + VecStr(inner_size_m));
  if (!AllFinite(growth_m)) return Fail(error, "growth_m must be finite");
  if ((growth_m.array() < 0).any())
    return Fail(error, "growth_m must be >= 0, got " + VecStr(growth_m));
  if (!std::isfinite(outer_density_m) || outer_density_m < 0)
    return Fail(error, "outer_density_m must be finite and >= 0");
  if (!std::isfinite(inner_density_m) || inner_density_m < 0)
    return Fail(error, "inner_density_m must be finite and >= 0");
  if (!std::isfinite(outer_keypoint_radius_m) || outer_keypoint_radius_m <= 0)
    return Fail(error, "outer_keypoint_radius_m must be finite and > 0");
  if (!std::isfinite(inner_keypoint_radius_m) || inner_keypoint_radius_m <= 0)
    return Fail(error, "inner_keypoint_radius_m must be finite and > 0");
  return true;
}

float LevelDensity(const FoveaOptions& o, int k) {
  return o.outer_density_m + k * (o.inner_density_m - o.outer_density_m) / o.finest_level;
}

float LevelKeypointRadius(const FoveaOptions& o, int k) {
  return o.outer_keypoint_radius_m +
         k * (o.inner_keypoint_radius_m - o.outer_keypoint_radius_m) / o.finest_level;
}

Eigen::Vector3f LevelDisplacement(int k, int m, const Eigen::Vector3f& outer_size,
                                  const Eigen::Vector3f& inner_size, const Eigen::Vector3f& fovea) {
  return static_cast<float>(k) * (outer_size - inner_size + 2.0f * fovea) / (2.0f * m);
}

Eigen::Vector3f LevelSize(int k, int m, const Eigen::Vector3f& outer_size,
                          const Eigen::Vector3f& inner_size) {
  // Eq. 2 rearranged as S_0 + k (S_m - S_0) / m, so that S_0 comes out exactly at k = 0.
  return outer_size + static_cast<float>(k) * (inner_size - outer_size) / static_cast<float>(m);
}

std::optional<Box> BoundingBox(const Cloud& cloud) {
  Box box;
  box.min.setConstant(std::numeric_limits<float>::infinity());
  box.max.setConstant(-std::numeric_limits<float>::infinity());
  bool any = false;
  for (const auto& p : cloud.points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    const Eigen::Vector3f v = p.getVector3fMap();
    box.min = box.min.cwiseMin(v);
    box.max = box.max.cwiseMax(v);
    any = true;
  }
  if (!any) return std::nullopt;
  return box;
}

FoveaGeometry ComputeFoveaGeometry(const FoveaOptions& o, const Box& scene_bounds,
                                   const Eigen::Vector3f& fovea_camera) {
  SACCADE_CHECK_VALID(o);
  FoveaGeometry g;
  Eigen::Vector3f origin;
  if (o.outer_box_from_scene) {
    // The scene's box, grown symmetrically where it is thinner than the fovea's own box, and by
    // a millimetre so that rounding never drops a point on its faces.
    const Eigen::Vector3f size =
        (scene_bounds.Size() + Eigen::Vector3f::Constant(2e-3f)).cwiseMax(o.inner_size_m);
    const Eigen::Vector3f centre = 0.5f * (scene_bounds.min + scene_bounds.max);
    origin = centre - 0.5f * size;
    g.outer_size_m = size;
    g.box_from_camera = Eigen::Translation3f(-origin);
  } else {
    origin = o.outer_min_corner_m;
    g.outer_size_m = o.outer_size_m;
    const Eigen::Matrix3f R_CB = o.outer_orientation.normalized().toRotationMatrix();
    g.box_from_camera.linear() = R_CB.transpose();
    g.box_from_camera.translation() = -(R_CB.transpose() * origin);
  }
  g.fovea_in_box_m = g.box_from_camera * fovea_camera;
  const Eigen::Vector3f F = g.fovea_in_box_m - 0.5f * g.outer_size_m;  // relative to centre
  const int m = o.finest_level;
  g.levels.resize(m + 1);
  for (int k = 0; k <= m; ++k) {
    const Eigen::Vector3f delta = LevelDisplacement(k, m, g.outer_size_m, o.inner_size_m, F);
    const Eigen::Vector3f size = LevelSize(k, m, g.outer_size_m, o.inner_size_m);
    g.levels[k].min = (delta - o.growth_m).cwiseMax(Eigen::Vector3f::Zero());
    g.levels[k].max = (delta + size + o.growth_m).cwiseMin(g.outer_size_m);
    // Exact arithmetic nests the boxes; this keeps them nested under float rounding too.
    if (k > 0) {
      g.levels[k].min = g.levels[k].min.cwiseMax(g.levels[k - 1].min);
      g.levels[k].max = g.levels[k].max.cwiseMin(g.levels[k - 1].max);
    }
  }
  return g;
}

int LevelOf(const FoveaGeometry& g, const Eigen::Vector3f& point_camera) {
  if (!point_camera.allFinite()) return -1;
  const Eigen::Vector3f p = g.box_from_camera * point_camera;
  const int m = static_cast<int>(g.levels.size()) - 1;
  // Literally Algorithm 1: the level whose box holds p while box k+1 does not.
  for (int k = 0; k <= m; ++k) {
    if (g.levels[k].Contains(p) && (k == m || !g.levels[k + 1].Contains(p))) return k;
  }
  return -1;
}

std::vector<int> VoxelRepresentatives(const Cloud& cloud, const std::vector<int>& candidates,
                                      float leaf_m) {
  if (leaf_m <= 0.0f) return candidates;
  const float inv = 1.0f / leaf_m;
  struct Slot {
    int index;
    float sqr_dist;
  };
  std::vector<Slot> slots;
  std::unordered_map<std::uint64_t, std::uint32_t> slot_of;
  slot_of.reserve(candidates.size() / 4 + 16);
  std::uint64_t last_key = ~std::uint64_t{0};
  std::uint32_t last_slot = 0;
  for (int i : candidates) {
    const Eigen::Vector3f p = cloud[i].getVector3fMap();
    const Eigen::Vector3f s = p * inv;
    const Eigen::Array3f cell = s.array().floor();
    // 21 bits per axis: +-1M voxels, far beyond any depth sensor's range at millimetre leaves.
    const auto key =
        (static_cast<std::uint64_t>(static_cast<std::int64_t>(cell.x()) & 0x1FFFFF)) |
        (static_cast<std::uint64_t>(static_cast<std::int64_t>(cell.y()) & 0x1FFFFF) << 21) |
        (static_cast<std::uint64_t>(static_cast<std::int64_t>(cell.z()) & 0x1FFFFF) << 42);
    const float d = (s.array() - cell - 0.5f).matrix().squaredNorm();
    std::uint32_t slot;
    if (key == last_key) {
      slot = last_slot;
    } else {
      auto [it, inserted] = slot_of.try_emplace(key, static_cast<std::uint32_t>(slots.size()));
      if (inserted) {
        slots.push_back({i, d});
        last_key = key;
        last_slot = it->second;
        continue;
      }
      slot = it->second;
      last_key = key;
      last_slot = slot;
    }
    if (d < slots[slot].sqr_dist) slots[slot] = {i, d};
  }
  std::vector<int> out;
  out.reserve(slots.size());
  for (const Slot& s : slots) out.push_back(s.index);
  return out;
}

namespace {

// The pixel rectangle [u0, u1] x [v0, v1] that `box` (box coordinates) can project to; the
// whole image when part of the box is at or behind the camera plane.
void ProjectedRect(const FoveaGeometry& g, const Box& box, const CameraIntrinsics& k, int w, int h,
                   int* u0, int* u1, int* v0, int* v1) {
  *u0 = 0, *u1 = w - 1, *v0 = 0, *v1 = h - 1;
  if (box.Empty()) {
    *u1 = *v1 = -1;
    return;
  }
  const Eigen::Isometry3f X_CB = g.box_from_camera.inverse();
  float umin = 1e30f, umax = -1e30f, vmin = 1e30f, vmax = -1e30f;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3f corner((c & 1) ? box.max.x() : box.min.x(),
                                 (c & 2) ? box.max.y() : box.min.y(),
                                 (c & 4) ? box.max.z() : box.min.z());
    const Eigen::Vector3f p = X_CB * corner;
    if (p.z() < 0.05f) return;
    const Eigen::Vector2f uv = k.Project(p).cast<float>();
    const float u = uv.x(), v = uv.y();
    umin = std::min(umin, u), umax = std::max(umax, u);
    vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  }
  *u0 = std::max(0, static_cast<int>(std::floor(umin)) - 1);
  *u1 = std::min(w - 1, static_cast<int>(std::ceil(umax)) + 1);
  *v0 = std::max(0, static_cast<int>(std::floor(vmin)) - 1);
  *v1 = std::min(h - 1, static_cast<int>(std::ceil(vmax)) + 1);
}

}  // namespace

std::vector<std::vector<int>> FoveateIndices(const Cloud& scene, const FoveaOptions& options,
                                             const FoveaGeometry& geometry, int first_level,
                                             const CameraIntrinsics* intrinsics) {
  const int m = static_cast<int>(geometry.levels.size()) - 1;
  std::vector<std::vector<int>> per_level(m + 1);
  const Eigen::Isometry3f& X_BC = geometry.box_from_camera;
  const bool axis_aligned = X_BC.linear().isIdentity(0.0f);
  const Eigen::Vector3f t = X_BC.translation();
  const int w = static_cast<int>(scene.width);
  const int h = static_cast<int>(scene.height);
  int u0 = 0, u1 = w - 1, v0 = 0, v1 = h - 1;
  if (intrinsics && h > 1 && first_level > 0)
    ProjectedRect(geometry, geometry.levels[first_level], *intrinsics, w, h, &u0, &u1, &v0, &v1);
  if (h <= 1) u0 = 0, u1 = static_cast<int>(scene.size()) - 1, v0 = 0, v1 = 0;
  const int row_stride = h <= 1 ? 0 : w;
  for (int v = v0; v <= v1; ++v) {
    for (int u = u0; u <= u1; ++u) {
      const int i = v * row_stride + u;
      const auto& pt = scene[i];
      if (!std::isfinite(pt.z) || !std::isfinite(pt.x) || !std::isfinite(pt.y)) continue;
      const Eigen::Vector3f p = axis_aligned ? Eigen::Vector3f(pt.getVector3fMap() + t)
                                             : Eigen::Vector3f(X_BC * pt.getVector3fMap());
      // Innermost box first: a point of the fovea never tests the outer levels. The boxes are
      // nested, so this is Algorithm 1's "inside box k and not inside box k+1".
      for (int k = m; k >= first_level; --k) {
        if (geometry.levels[k].Contains(p)) {
          per_level[k].push_back(i);
          break;
        }
      }
    }
  }
  for (int k = first_level; k <= m; ++k)
    per_level[k] = VoxelRepresentatives(scene, per_level[k], LevelDensity(options, k));
  return per_level;
}

FoveatedCloud Foveate(const Cloud& scene, const FoveaOptions& options,
                      const FoveaGeometry& geometry) {
  const std::vector<std::vector<int>> per_level = FoveateIndices(scene, options, geometry);
  FoveatedCloud out;
  out.geometry = geometry;
  out.level_begin.assign(1, 0);
  for (std::size_t k = 0; k < per_level.size(); ++k) {
    for (int i : per_level[k]) {
      out.cloud.push_back(scene[i]);
      out.source_index.push_back(i);
      out.level.push_back(static_cast<std::uint8_t>(k));
    }
    out.level_begin.push_back(out.cloud.size());
  }
  out.cloud.width = static_cast<std::uint32_t>(out.cloud.size());
  out.cloud.height = 1;
  out.cloud.is_dense = true;
  return out;
}

Cloud FoveatedCloud::LevelCloud(int k) const {
  Cloud c;
  c.points.assign(cloud.points.begin() + level_begin[k], cloud.points.begin() + level_begin[k + 1]);
  c.width = static_cast<std::uint32_t>(c.size());
  c.height = 1;
  c.is_dense = true;
  return c;
}

}  // namespace saccade
