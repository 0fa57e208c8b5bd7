#include "core/sim/rerender.h"

#include "core/check.h"
#include "core/fail.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace saccade {

Cloud RerenderCapture(const Cloud& world, const CameraIntrinsics& k, const RerenderPose& pose,
                      std::vector<std::uint8_t>* labels) {
  SACCADE_CHECK(world.height > 1, "an organized capture");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Cloud out(static_cast<std::uint32_t>(k.width), static_cast<std::uint32_t>(k.height));
  out.is_dense = false;
  for (PointT& p : out.points) {
    p.x = p.y = p.z = nan;
    p.r = p.g = p.b = 0;
    p.a = 255;
  }
  std::vector<float> depth(out.size(), std::numeric_limits<float>::infinity());
  if (labels) labels->assign(out.size(), 0);
  // Per capture point: 1 the moving object's, 2 + j others[j]'s, 0 the rest.
  std::vector<std::uint8_t> tag(world.size(), 0);
  const auto mark = [&](const std::vector<int>& indices, std::uint8_t value) {
    for (int i : indices)
      if (i >= 0 && static_cast<std::size_t>(i) < world.size())
        tag[static_cast<std::size_t>(i)] = value;
  };
  for (std::size_t j = 0; j < pose.others.size() && j < 253; ++j)
    mark(pose.others[j], static_cast<std::uint8_t>(2 + j));
  mark(pose.object, 1);
  const Eigen::Isometry3f X_CW = pose.X_WC.inverse();
  const Eigen::Isometry3f X_CW_moved = X_CW * pose.object_motion_W;
  for (std::size_t i = 0; i < world.size(); ++i) {
    const PointT& w = world[i];
    if (!FinitePoint(w) || !(w.z > 0)) continue;
    const Eigen::Vector3f p = (tag[i] == 1 ? X_CW_moved : X_CW) * w.getVector3fMap();
    if (!(p.z() > 0.05f)) continue;
    const Eigen::Vector2d uv = k.Project(p);
    // The capture's pixel at depth w.z covers (w.z / p.z) pixels at the new depth: one pixel
    // at the captured depth or farther, a (2r+1)-pixel square when the camera came nearer.
    const int r = static_cast<int>(std::lround(0.5 * std::max(1.0, double(w.z) / p.z()) - 0.5));
    const int cu = static_cast<int>(std::lround(uv.x())),
              cv = static_cast<int>(std::lround(uv.y()));
    const int u0 = std::max(0, cu - r), u1 = std::min(k.width - 1, cu + r);
    const int v0 = std::max(0, cv - r), v1 = std::min(k.height - 1, cv + r);
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) {
        const std::size_t j = static_cast<std::size_t>(v) * k.width + u;
        if (p.z() >= depth[j]) continue;
        depth[j] = p.z();
        PointT& o = out[j];
        // The pixel's own ray at the splatted point's depth: a splat is a patch facing the
        // camera, as a depth sensor would report it.
        o.getVector3fMap() = k.Unproject(u, v, p.z());
        o.r = w.r, o.g = w.g, o.b = w.b, o.a = w.a;
        if (labels) (*labels)[j] = tag[i];
      }
  }
  return out;
}

namespace {

// The board of an occluded frame: facing the camera, centred on its line of sight to `target`
// (camera frame), occluder_distance_m nearer than it; pixels where it is nearer than what was
// rendered see the board (grey), and lose the object's label.
void PlaceOccluder(const CaptureSequence& s, const CameraIntrinsics& k,
                   const Eigen::Vector3f& target, Cloud* cloud, std::vector<std::uint8_t>* labels) {
  const float distance = target.norm();
  if (!(distance > s.occluder_distance_m + 0.05f)) return;
  const Eigen::Vector3f axis = target / distance;
  const Eigen::Vector3f centre = axis * (distance - s.occluder_distance_m);
  // The board's axes: horizontal (perpendicular to the line of sight and the camera's y) and
  // vertical.
  const Eigen::Vector3f across = Eigen::Vector3f::UnitY().cross(axis).normalized();
  const Eigen::Vector3f up = axis.cross(across);
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3f ray = k.Unproject(u, v, 1.0).normalized();
      const float along = ray.dot(axis);
      if (!(along > 1e-3f)) continue;
      const Eigen::Vector3f hit = ray * (centre.dot(axis) / along);  // on the board's plane
      const Eigen::Vector3f d = hit - centre;
      if (std::abs(d.dot(across)) > s.occluder_size_m.x() / 2 ||
          std::abs(d.dot(up)) > s.occluder_size_m.y() / 2)
        continue;
      const std::size_t j = static_cast<std::size_t>(v) * k.width + u;
      PointT& p = (*cloud)[j];
      if (FinitePoint(p) && p.z <= hit.z()) continue;
      p.getVector3fMap() = k.Unproject(u, v, hit.z());
      p.r = p.g = p.b = 128;
      (*labels)[j] = 0;
    }
}

}  // namespace

bool CaptureSequence::IsValid(std::string* error) const {
  if (capture.empty()) return Fail(error, "capture: a labelled PCD file is required");
  if (object < 1) return Fail(error, "object must be >= 1");
  for (int o : others)
    if (o < 1 || o == object) return Fail(error, "others must be objects >= 1 other than object");
  if (frames < 1 || frames > kMaxSequenceFrames)
    return Fail(error, "frames must be 1-" + std::to_string(kMaxSequenceFrames));
  if (!(rate_hz >= 0.01 && rate_hz <= 1000)) return Fail(error, "rate_hz must be 0.01-1000 Hz");
  if (occluded_frames < 0) return Fail(error, "occluded_frames must be >= 0");
  if (!((occluder_size_m.array() > 0).all())) return Fail(error, "occluder_size_m must be > 0");
  if (!(occluder_distance_m > 0)) return Fail(error, "occluder_distance_m must be > 0");
  for (const Trajectory* m : {&camera_motion, &object_motion})
    if (!(m->period_s > 0)) return Fail(error, "trajectory period_s must be > 0");
  return true;
}

std::vector<int> MosdObjectPoints(const Cloud& cloud, const std::vector<std::uint32_t>& labels,
                                  int object) {
  std::vector<int> out;
  for (std::size_t i = 0; i < labels.size() && i < cloud.size(); ++i)
    if (labels[i] >= 10 && static_cast<int>(labels[i] / 10) == object && FinitePoint(cloud[i]))
      out.push_back(static_cast<int>(i));
  return out;
}

CaptureFrame RenderCaptureFrame(const CaptureSequence& sequence, const LoadedCapture& capture,
                                int index) {
  CaptureFrame f;
  f.time_s = index / sequence.rate_hz;
  RerenderPose pose;
  pose.X_WC = PlanarPose(sequence.camera_motion, f.time_s);
  pose.object = capture.object;
  pose.others = capture.others;
  const Eigen::Vector3f& c = capture.object_centroid;
  pose.object_motion_W = Eigen::Translation3f(c) * PlanarPose(sequence.object_motion, f.time_s) *
                         Eigen::Translation3f(-c);
  std::vector<std::uint8_t> labels;
  f.cloud = RerenderCapture(capture.cloud, capture.intrinsics, pose, &labels);
  const Eigen::Isometry3f X_CO = pose.X_WC.inverse() * pose.object_motion_W;
  f.truth.target_pose = X_CO;
  f.truth.centroid_m = X_CO * c;
  if (index >= sequence.occluded_from && index < sequence.occluded_from + sequence.occluded_frames)
    PlaceOccluder(sequence, capture.intrinsics, f.truth.centroid_m, &f.cloud, &labels);
  // Visible share: the pixels each object won over its points in the capture.
  std::vector<std::size_t> seen(2 + capture.others.size(), 0);
  for (std::uint8_t l : labels)
    if (l < seen.size()) ++seen[l];
  const auto share = [](std::size_t won, std::size_t points) {
    return points == 0 ? 0.0f : std::min(1.0f, float(won) / float(points));
  };
  f.truth.visible_fraction = share(seen[1], capture.object.size());
  const Eigen::Isometry3f X_CW = pose.X_WC.inverse();
  for (std::size_t j = 0; j < capture.others.size(); ++j) {
    GroundTruth::Object o;
    o.pose = X_CW;
    o.centroid_m = X_CW * capture.other_centroids[j];
    o.visible_fraction = share(seen[2 + j], capture.others[j].size());
    f.truth.others.push_back(o);
  }
  return f;
}

}  // namespace saccade
