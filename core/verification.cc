#include "core/verification.h"

#include "core/colour.h"
#include "core/fail.h"
#include "core/features.h"
#include "core/foveation.h"
#include "core/nearest_within.h"
#include "core/tracking.h"

#include <flann/algorithms/dist.h>
#include <flann/algorithms/kdtree_single_index.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace saccade {

bool VerificationOptions::IsValid(std::string* error) const {
  if (max_candidates < 1) return Fail(error, "verify_candidates must be >= 1");
  if (model_points < 10) return Fail(error, "verify_model_points must be >= 10");
  if (icp_points < 10) return Fail(error, "verify_icp_points must be >= 10");
  if (icp_iterations < 0) return Fail(error, "verify_icp_iterations must be >= 0");
  const std::pair<const char*, float> positive[] = {
      {"verify_icp_max_distance_m", icp_max_distance_m},
      {"verify_inlier_distance_m", inlier_distance_m},
      {"verify_max_sink_m", max_sink_m}};
  for (const auto& [name, v] : positive)
    if (!(std::isfinite(v) && v > 0)) return Fail(error, std::string(name) + " must be > 0");
  const std::pair<const char*, float> shares[] = {
      {"verify_min_fitness", min_fitness},
      {"verify_min_coverage", min_coverage},
      {"verify_min_depth_ratio", min_depth_ratio},
      {"verify_min_colour_agreement", min_colour_agreement},
      {"verify_min_confidence", min_confidence},
      {"verify_min_view_confidence", min_view_confidence},
      {"verify_max_continued", max_continued}};
  for (const auto& [name, v] : shares)
    if (!(v >= 0 && v <= 1)) return Fail(error, std::string(name) + " must be in [0, 1]");
  return true;
}

namespace {

// The scene's finite points within `radius_m` of `centre`: for an organized scene only the pixel
// rectangle the sphere can project into is scanned, every `spacing_m` (in pixels at the centre's
// depth) rather than every pixel: a surface sampled that finely still puts a point within
// spacing_m of any point on it, and the search over it is built in a fraction of the time.
// Returns x, y, z of each kept point in turn; `indices` gets their scene indices.
std::vector<float> Crop(const Cloud& scene, const std::optional<CameraIntrinsics>& k,
                        const Eigen::Vector3f& centre, float radius_m, float spacing_m,
                        std::vector<int>* indices) {
  int u0 = 0, u1 = int(scene.width) - 1, v0 = 0, v1 = int(scene.height) - 1, step = 1;
  const float near_z = centre.z() - radius_m;
  if (k && scene.height > 1 && near_z > 0.05f) {
    const Eigen::Vector2f uv = k->Project(centre).cast<float>();
    const float u = uv.x(), v = uv.y();
    const float half = float(std::max(k->fx, k->fy)) * radius_m / near_z + 1;
    u0 = std::max(u0, int(std::floor(u - half)));
    u1 = std::min(u1, int(std::ceil(u + half)));
    v0 = std::max(v0, int(std::floor(v - half)));
    v1 = std::min(v1, int(std::ceil(v + half)));
    step = std::max(1, int(spacing_m * float(std::min(k->fx, k->fy)) / centre.z()));
  }
  std::vector<float> out;
  const float r2 = radius_m * radius_m;
  for (int v = v0; v <= v1; v += step)
    for (int u = u0; u <= u1; u += step) {
      const int i = v * int(scene.width) + u;
      const Eigen::Vector3f p = scene[i].getVector3fMap();
      if (!p.allFinite() || (p - centre).squaredNorm() > r2) continue;
      out.insert(out.end(), {p.x(), p.y(), p.z()});
      indices->push_back(i);
    }
  return out;
}

// The nearest of a set of points within a given distance, through FLANN's single kd-tree
// directly: PCL's wrapper spends more per query (a copy of the query, an OpenMP region, index
// conversions) than the search itself, and ICP asks thousands of times per candidate.
class NearestIndex {
 public:
  // `xyz`: x, y, z of each point in turn, at least one point.
  explicit NearestIndex(std::vector<float> xyz)
      : xyz_(std::move(xyz)),
        index_(flann::Matrix<float>(xyz_.data(), xyz_.size() / 3, 3),
               flann::KDTreeSingleIndexParams(10, false)) {
    index_.buildIndex();
  }
  NearestIndex(const NearestIndex&) = delete;  // the index points into xyz_
  NearestIndex& operator=(const NearestIndex&) = delete;

  const float* point(int i) const { return xyz_.data() + 3 * i; }

  // The nearest point's index and squared distance; index -1 when none is within
  // sqrt(max_sqr_distance) (a point at exactly that distance counts).
  std::pair<int, float> Nearest(const Eigen::Vector3f& p, float max_sqr_distance) const {
    NearestWithin result(max_sqr_distance);
    index_.findNeighbors(result, p.data(), flann::SearchParams());
    return {result.index(), result.sqr_distance()};
  }

 private:
  std::vector<float> xyz_;  // before index_, which points into it
  flann::KDTreeSingleIndex<flann::L2_Simple<float>> index_;
};

struct Check {
  Eigen::Matrix4f pose;
  int inliers = 0, against = 0;
  float thickness = 0;  // of the inlying model points: sqrt of their least covariance eigenvalue
  int counted = 0;      // model points counted: all, or a whole surface's facing the camera
  float counted_thickness = 0;  // of the counted points
  float continued = -1;         // ContinuedShare of the counted points, -1 when not measured
  std::vector<int> explained;   // scene points nearest the inlying model points
  std::vector<int> explaining;  // the inlying model points, one per explained scene point
};

// The spread of points along their least-spread direction (0 when planar or too few).
float Thickness(const std::vector<Eigen::Vector3f>& points) {
  if (points.size() < 4) return 0;
  return float(std::sqrt(std::max(0.0, ComputePrincipalAxes(points).variances[0])));
}

// ICP from `pose`, then counts model points on the surface and against the hypothesis (in front
// of the seen surface, or sunk just behind it while facing the camera).
Check Refine(const VerificationModel& model, const Cloud& scene,
             const std::optional<CameraIntrinsics>& k, const Eigen::Matrix4f& pose,
             const VerificationOptions& o) {
  Check c;
  c.pose = pose;
  const Eigen::Vector3f centre = (pose * model.centre.homogeneous()).head<3>();
  std::vector<int> crop_index;
  // Sampled half an inlier distance apart, the nearest scene point is at most ~0.35 inlier
  // distances farther than on the full grid: a model point on the surface stays an inlier.
  std::vector<float> xyz = Crop(scene, k, centre, model.radius_m + o.icp_max_distance_m + 0.01f,
                                o.inlier_distance_m / 2, &crop_index);
  if (xyz.size() < 3 * 10) return c;
  const NearestIndex crop(std::move(xyz));
  const std::size_t n_points = model.points.size();
  // A whole-surface model's point counts only where the pose turns it towards the camera (a
  // mesh's: and not almost edge-on, model.min_facing).
  const auto faces_camera = [&](std::size_t m, const Eigen::Vector3f& p) {
    if (!model.whole_surface) return true;
    const Eigen::Vector3f n = c.pose.topLeftCorner<3, 3>() * model.normals[m];
    return !n.allFinite() || n.dot(p) < -model.min_facing * p.norm();
  };
  // ICP aligns an even subset of the points; all of them are counted afterwards.
  const std::size_t icp_step = std::max<std::size_t>(1, n_points / std::max(1, o.icp_points));
  Eigen::Matrix3Xd src(3, n_points), dst(3, n_points);
  for (int it = 0; it < o.icp_iterations; ++it) {
    const float t = o.icp_iterations > 1 ? float(it) / float(o.icp_iterations - 1) : 1.0f;
    const float max_d = o.icp_max_distance_m * (1 - t) + 2 * o.inlier_distance_m * t;
    int n = 0;
    for (std::size_t m = 0; m < n_points; m += icp_step) {
      const Eigen::Vector3f p = (c.pose * model.points[m].getVector3fMap().homogeneous()).head<3>();
      if (!faces_camera(m, p)) continue;
      const int j = crop.Nearest(p, max_d * max_d).first;
      if (j < 0) continue;
      src.col(n) = p.cast<double>();
      dst.col(n) = Eigen::Map<const Eigen::Vector3f>(crop.point(j)).cast<double>();
      ++n;
    }
    if (n < 10) break;
    // In double: GCC 12 sees a false out-of-bounds read in Eigen's float umeyama.
    const Eigen::Matrix4f step =
        Eigen::umeyama(src.leftCols(n), dst.leftCols(n), false).cast<float>();
    c.pose = step * c.pose;
    if ((step.topRightCorner<3, 1>().norm() < 1e-4f) &&
        (step.topLeftCorner<3, 3>() - Eigen::Matrix3f::Identity()).norm() < 1e-4f)
      break;
  }
  // A mesh's normals are exact: the tracker's point-to-plane steps against the frame then turn
  // its flat faces into place, where point-to-point lets them slide (the ViSP cube,
  // docs/RESULTS.md). The polished pose is kept when it holds and lays at least as many model
  // points on the frame as ICP's. The tracker's default options: tracking.refine is a daemon
  // setting that recognition does not see (they are saccaded.yaml's too).
  if (model.whole_surface && model.min_facing > 0 && k && scene.height > 1 &&
      int(scene.width) == k->width && int(scene.height) == k->height) {
    const TrackOptions polish;
    const TrackResult polished = TrackPose(model, scene, *k, c.pose, polish);
    if (polished.tracking &&
        polished.inliers >= ScorePose(model, scene, *k, c.pose, polish).inliers)
      c.pose = polished.model_to_camera;
  }
  const float tolerance = 2 * o.inlier_distance_m;
  const Eigen::Matrix3f R = c.pose.topLeftCorner<3, 3>();
  std::vector<Eigen::Vector3f> facing;  // the points counted, model frame
  const bool outline = k && scene.height > 1;
  std::vector<Eigen::Vector3f> seen;  // the points counted, camera frame, for the outline
  for (std::size_t m = 0; m < n_points; ++m) {
    const Eigen::Vector3f p = (c.pose * model.points[m].getVector3fMap().homogeneous()).head<3>();
    if (!faces_camera(m, p)) continue;
    if (model.whole_surface) facing.push_back(model.points[m].getVector3fMap());
    if (outline) seen.push_back(p);
    const int j = crop.Nearest(p, o.inlier_distance_m * o.inlier_distance_m).first;
    if (j >= 0) {
      ++c.inliers;
      c.explained.push_back(crop_index[j]);
      c.explaining.push_back(int(m));
      continue;
    }
    if (!k || scene.height <= 1 || p.z() <= 0) continue;
    const int u = int(std::lround(k->fx * p.x() / p.z() + k->cx));
    const int v = int(std::lround(k->fy * p.y() / p.z() + k->cy));
    if (u < 0 || v < 0 || u >= int(scene.width) || v >= int(scene.height)) continue;
    const float seen = scene.at(u, v).z;
    if (!std::isfinite(seen)) continue;
    if (p.z() < seen - tolerance) {
      ++c.against;  // it would hide what the sensor saw
    } else if (p.z() > seen + tolerance && p.z() < seen + o.max_sink_m) {
      const Eigen::Vector3f n = R * model.normals[m];
      if (n.allFinite() && n.dot(p.normalized()) < -0.3f) ++c.against;  // facing us, sunk
    }
  }
  std::vector<Eigen::Vector3f> on_surface;  // the inlying model points, model frame
  for (int m : c.explaining) on_surface.push_back(model.points[m].getVector3fMap());
  c.thickness = Thickness(on_surface);
  c.counted = model.whole_surface ? int(facing.size()) : int(n_points);
  c.counted_thickness = model.whole_surface ? Thickness(facing) : model.thickness_m;
  if (outline) c.continued = ContinuedShare(seen, model.spacing_m, scene, *k, tolerance);
  return c;
}

// The median distance from each point to its nearest other point (0 with fewer than two).
float MedianSpacing(const Cloud& points) {
  std::vector<float> nearest;
  for (std::size_t i = 0; i < points.size(); ++i) {
    float best = std::numeric_limits<float>::infinity();
    for (std::size_t j = 0; j < points.size(); ++j)
      if (j != i)
        best =
            std::min(best, (points[i].getVector3fMap() - points[j].getVector3fMap()).squaredNorm());
    if (std::isfinite(best)) nearest.push_back(best);
  }
  if (nearest.empty()) return 0;
  auto mid = nearest.begin() + nearest.size() / 2;
  std::nth_element(nearest.begin(), mid, nearest.end());
  return std::sqrt(*mid);
}

// Brightness of a point's colour (Rec. 601 luma), 0-255.
float Luma(const PointT& p) {
  return 0.299f * float(p.r) + 0.587f * float(p.g) + 0.114f * float(p.b);
}

}  // namespace

float ContinuedShare(const std::vector<Eigen::Vector3f>& points, float spacing_m,
                     const Cloud& scene, const CameraIntrinsics& k, float tolerance_m) {
  if (points.size() < 10 || spacing_m <= 0 || scene.height <= 1) return -1;
  std::vector<Eigen::Vector3f> uvz;  // pixel column, row, depth
  double z_sum = 0;
  for (const Eigen::Vector3f& p : points) {
    if (!(p.z() > 0.05f)) continue;
    uvz.emplace_back(float(k.fx) * p.x() / p.z() + float(k.cx),
                     float(k.fy) * p.y() / p.z() + float(k.cy), p.z());
    z_sum += p.z();
  }
  if (uvz.size() < 10) return -1;
  // Cells two point spacings wide at the points' mean depth: the points leave no hole inside.
  const float z_mean = float(z_sum / double(uvz.size()));
  const float cell = std::max(2.0f, 2.0f * float(std::max(k.fx, k.fy)) * spacing_m / z_mean);
  Eigen::Vector2f lo = uvz.front().head<2>(), hi = lo;
  for (const Eigen::Vector3f& q : uvz) lo = lo.cwiseMin(q.head<2>()), hi = hi.cwiseMax(q.head<2>());
  const Eigen::Vector2f origin = lo - Eigen::Vector2f::Constant(2 * cell);
  const int w = int((hi.x() - lo.x()) / cell) + 5, h = int((hi.y() - lo.y()) / cell) + 5;
  if (w > 1024 || h > 1024) return -1;  // a pose far off the frame's scale
  constexpr float kNone = std::numeric_limits<float>::infinity();
  std::vector<float> depth(std::size_t(w) * std::size_t(h), kNone);  // nearest point per cell
  const auto at = [&](int x, int y) { return std::size_t(y) * std::size_t(w) + std::size_t(x); };
  for (const Eigen::Vector3f& q : uvz) {
    const int x = int((q.x() - origin.x()) / cell), y = int((q.y() - origin.y()) / cell);
    depth[at(x, y)] = std::min(depth[at(x, y)], q.z());
  }
  // Inside: a cell with points, or between two cells with points (a hole of one cell).
  const auto on_grid = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h; };
  const auto has = [&](int x, int y) { return on_grid(x, y) && depth[at(x, y)] < kNone; };
  std::vector<std::uint8_t> inside(depth.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      inside[at(x, y)] =
          has(x, y) || (has(x - 1, y) && has(x + 1, y)) || (has(x, y - 1) && has(x, y + 1));
  const auto in = [&](int x, int y) { return on_grid(x, y) && inside[at(x, y)]; };
  int continued = 0, outline = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (in(x, y) || !(in(x - 1, y) || in(x + 1, y) || in(x, y - 1) || in(x, y + 1))) continue;
      float z = kNone;  // the depth of the nearest points beside this place
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (has(x + dx, y + dy)) z = std::min(z, depth[at(x + dx, y + dy)]);
      if (z == kNone) continue;
      const int u = int(origin.x() + (float(x) + 0.5f) * cell);
      const int v = int(origin.y() + (float(y) + 0.5f) * cell);
      if (u < 0 || v < 0 || u >= int(scene.width) || v >= int(scene.height)) continue;
      const float seen = scene.at(u, v).z;
      if (!std::isfinite(seen)) {
        ++outline;  // nothing seen there: a shadow or a silhouette's edge
      } else if (seen < z - tolerance_m) {
        continue;  // something in front: it says nothing of the outline
      } else if (seen <= z + tolerance_m) {
        ++continued;
      } else {
        ++outline;  // the sensor sees past the points
      }
    }
  return continued + outline > 0 ? float(continued) / float(continued + outline) : -1;
}

float TextureAgreement(const Cloud& model, const std::vector<int>& model_points, const Cloud& scene,
                       const std::vector<int>& scene_points) {
  constexpr float kMinSpread = 8;  // grey levels: below it a surface is too plain to compare
  const std::size_t n = std::min(model_points.size(), scene_points.size());
  if (n < 20) return -1;
  double sm = 0, ss = 0, smm = 0, sss = 0, sms = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double m = Luma(model[model_points[i]]), s = Luma(scene[scene_points[i]]);
    sm += m, ss += s, smm += m * m, sss += s * s, sms += m * s;
  }
  const double vm = smm / double(n) - (sm / double(n)) * (sm / double(n));
  const double vs = sss / double(n) - (ss / double(n)) * (ss / double(n));
  if (vm < kMinSpread * kMinSpread || vs < kMinSpread * kMinSpread) return -1;
  const double cov = sms / double(n) - (sm / double(n)) * (ss / double(n));
  return float(std::clamp(cov / std::sqrt(vm * vs), -1.0, 1.0));
}

bool HasColour(const Cloud& cloud) {
  if (cloud.empty()) return false;
  const auto rgb = [](const PointT& p) { return p.rgba & 0xffffffu; };
  const std::uint32_t first = rgb(cloud[0]);
  for (const PointT& p : cloud.points)
    if (rgb(p) != first) return true;
  return false;
}

float InstanceConfidence(const Detection& d, float relative_fit) {
  // Logistic regressions fitted on the instances verification kept (every gate but this one)
  // on the cross-capture benchmark's 238 cases (docs/RESULTS.md, "Confidence"): features
  // 1, ln votes, fitness, coverage, colour agreement (when measured), relative fit.
  const double votes = std::log(std::max(1, d.votes));
  double z;
  if (d.colour_agreement >= 0)
    z = -9.107 + 1.243 * votes - 0.635 * d.fitness + 1.067 * d.coverage +
        5.237 * d.colour_agreement + 3.237 * relative_fit;
  else
    z = -9.009 + 1.630 * votes - 0.421 * d.fitness + 2.200 * d.coverage + 4.090 * relative_fit;
  return float(1 / (1 + std::exp(-z)));
}

const char* VerdictName(Verdict v) {
  switch (v) {
    case Verdict::kKept:
      return "kept";
    case Verdict::kNotChecked:
      return "not_checked";
    case Verdict::kNoFit:
      return "no_fit";
    case Verdict::kFlat:
      return "flat";
    case Verdict::kNoOutline:
      return "no_outline";
    case Verdict::kColour:
      return "colour";
    case Verdict::kUnconfident:
      return "unconfident";
    case Verdict::kTakenByBetter:
      return "taken_by_better";
    case Verdict::kFewVotes:
      return "few_votes";
  }
  return "?";
}

bool FailedACheck(Verdict v) {
  return v == Verdict::kNoFit || v == Verdict::kFlat || v == Verdict::kColour ||
         v == Verdict::kNoOutline || v == Verdict::kUnconfident;
}

VerificationModel MakeVerificationModel(const Cloud& model,
                                        const std::vector<Eigen::Vector3f>& normals,
                                        int max_points) {
  VerificationModel out;
  std::vector<int> finite;
  for (int i = 0; i < int(model.size()); ++i)
    if (model[i].getVector3fMap().allFinite()) finite.push_back(i);
  if (finite.empty()) return out;
  const double step = std::max(1.0, double(finite.size()) / std::max(1, max_points));
  for (double k = 0; k < double(finite.size()); k += step) {
    out.points.push_back(model[finite[int(k)]]);
    out.normals.push_back(normals[finite[int(k)]]);
  }
  const Box box = *BoundingBox(model);  // some point is finite
  out.centre = (box.min + box.max) / 2;
  out.radius_m = box.Size().norm() / 2;
  out.coloured = HasColour(model) && !MaterialGreys(model);
  std::vector<Eigen::Vector3f> all;
  for (const PointT& p : out.points) all.push_back(p.getVector3fMap());
  out.thickness_m = Thickness(all);
  out.spacing_m = MedianSpacing(out.points);
  return out;
}

std::vector<Detection> VerifyInstances(const VerificationModel& model,
                                       const Eigen::Vector3f& vote_point, const Cloud& scene,
                                       const std::optional<CameraIntrinsics>& intrinsics,
                                       std::vector<Detection> instances,
                                       const VerificationOptions& options,
                                       const ParallelFor& parallel_for,
                                       std::vector<Verdict>* verdicts) {
  std::vector<Verdict> verdict(instances.size(), Verdict::kNotChecked);
  if (model.points.empty() || instances.empty()) {
    if (verdicts) *verdicts = std::move(verdict);
    return {};
  }
  // Colour agreement is measured whenever both clouds have colour; it gates only when asked to.
  const bool colour = options.use_colour && model.coloured && HasColour(scene);
  if (int(instances.size()) > options.max_candidates) instances.resize(options.max_candidates);
  std::vector<Check> checks(instances.size());
  parallel_for(instances.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      checks[i] = Refine(model, scene, intrinsics, instances[i].model_to_scene, options);
  });
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < instances.size(); ++i) {
    const Check& c = checks[i];
    Detection& d = instances[i];
    d.fitness = c.inliers ? float(c.inliers) / float(c.inliers + c.against) : 0.0f;
    d.coverage = float(c.inliers) / float(std::max(1, c.counted));
    verdict[i] = Verdict::kNoFit;
    if (d.fitness < options.min_fitness || d.coverage < options.min_coverage) continue;
    verdict[i] = Verdict::kFlat;
    if (c.thickness < options.min_depth_ratio * c.counted_thickness) continue;
    d.continued = c.continued;
    verdict[i] = Verdict::kColour;
    if (colour) {
      // The same surface on both sides: the model points on the scene and the points they lie
      // on (the model's other faces may differ in colour and are not seen here).
      ColourHistogram on_model{}, seen{};
      for (int m : c.explaining) AddColour(model.points[m], &on_model);
      for (int j : c.explained) AddColour(scene[j], &seen);
      Normalize(&on_model);
      Normalize(&seen);
      d.colour_agreement = Intersection(on_model, seen);
      d.texture_agreement = TextureAgreement(model.points, c.explaining, scene, c.explained);
      if (options.min_colour_agreement > 0 && d.colour_agreement < options.min_colour_agreement)
        continue;
    }
    d.model_to_scene = c.pose;
    d.centroid_m = (c.pose * vote_point.homogeneous()).head<3>();
    verdict[i] = Verdict::kTakenByBetter;
    order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return instances[a].coverage * instances[a].fitness >
           instances[b].coverage * instances[b].fitness;
  });
  // One score from all the figures, against the best candidate's surface fit (the outline is
  // judged after: the confidence was calibrated against every candidate that fits).
  if (!order.empty()) {
    const float best = instances[order.front()].coverage * instances[order.front()].fitness;
    std::vector<std::size_t> confident;
    for (std::size_t i : order) {
      Detection& d = instances[i];
      d.confidence = InstanceConfidence(d, d.coverage * d.fitness / std::max(1e-6f, best));
      if (d.continued > options.max_continued)
        verdict[i] = Verdict::kNoOutline;
      else if (d.confidence >= options.min_confidence)
        confident.push_back(i);
      else
        verdict[i] = Verdict::kUnconfident;
    }
    order.swap(confident);
  }
  // Best first, and two instances cannot be one object: an instance that mostly re-explains
  // scene points a better one took, or whose body would overlap a better one's (centres closer
  // than the model's half diagonal), is the model slid along the object or onto its neighbour.
  std::vector<int> taken;  // sorted scene indices
  std::vector<Detection> out;
  std::vector<Eigen::Vector3f> centres;
  for (std::size_t i : order) {
    const Check& c = checks[i];
    const Eigen::Vector3f centre = (c.pose * model.centre.homogeneous()).head<3>();
    if (std::any_of(centres.begin(), centres.end(),
                    [&](const Eigen::Vector3f& o) { return (o - centre).norm() < model.radius_m; }))
      continue;
    int fresh = 0;
    for (int j : c.explained) fresh += !std::binary_search(taken.begin(), taken.end(), j);
    if (float(fresh) < options.min_coverage * float(c.counted) || fresh < c.inliers / 2) continue;
    taken.insert(taken.end(), c.explained.begin(), c.explained.end());
    std::sort(taken.begin(), taken.end());
    centres.push_back(centre);
    verdict[i] = Verdict::kKept;
    out.push_back(std::move(instances[i]));
  }
  if (verdicts) *verdicts = std::move(verdict);
  return out;
}

}  // namespace saccade
