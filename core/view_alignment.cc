#include "core/view_alignment.h"

#include "core/colour.h"
#include "core/features.h"
#include "core/recognition.h"
#include "core/verification.h"

#include <pcl/kdtree/kdtree_flann.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace saccade {
namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr FiniteXyz(const Cloud& cloud) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr out(new pcl::PointCloud<pcl::PointXYZ>);
  for (const PointT& p : cloud.points)
    if (FinitePoint(p)) out->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  return out;
}

Eigen::Vector3f Moved(const Eigen::Matrix4f& pose, const pcl::PointXYZ& p) {
  return (pose * Eigen::Vector4f(p.x, p.y, p.z, 1)).head<3>();
}

// Point-to-point ICP of `a` onto `b` from `pose`, the pairing distance shrinking from
// max_distance to inlier_distance.
Eigen::Matrix4f Icp(const pcl::PointCloud<pcl::PointXYZ>& a,
                    const pcl::KdTreeFLANN<pcl::PointXYZ>& b,
                    const pcl::PointCloud<pcl::PointXYZ>& b_points, Eigen::Matrix4f pose,
                    const AlignmentOptions& o) {
  pcl::Indices nn(1);
  std::vector<float> d2(1);
  const std::size_t step = std::max<std::size_t>(1, a.size() / 3000);
  for (int it = 0; it < o.icp_iterations; ++it) {
    const float t = o.icp_iterations > 1 ? float(it) / float(o.icp_iterations - 1) : 1.0f;
    const float max_d = o.icp_max_distance_m * (1 - t) + o.inlier_distance_m * t;
    std::vector<Eigen::Vector3f> src, dst;
    for (std::size_t i = 0; i < a.size(); i += step) {
      const Eigen::Vector3f p = Moved(pose, a[i]);
      if (b.nearestKSearch(pcl::PointXYZ(p.x(), p.y(), p.z()), 1, nn, d2) != 1) continue;
      if (d2[0] > max_d * max_d) continue;
      src.push_back(p);
      dst.push_back(b_points[std::size_t(nn[0])].getVector3fMap());
    }
    if (src.size() < 10) break;
    Eigen::Matrix3Xd from(3, long(src.size())), to(3, long(dst.size()));
    for (std::size_t i = 0; i < src.size(); ++i) {
      from.col(long(i)) = src[i].cast<double>();
      to.col(long(i)) = dst[i].cast<double>();
    }
    const Eigen::Matrix4f step_pose = Eigen::umeyama(from, to, false).cast<float>();
    if (!step_pose.allFinite()) break;
    pose = step_pose * pose;
  }
  return pose;
}

std::pair<float, float> Overlap(const pcl::PointCloud<pcl::PointXYZ>& a,
                                const Eigen::Matrix4f& pose,
                                const pcl::KdTreeFLANN<pcl::PointXYZ>& b, float inlier_distance_m) {
  if (a.empty()) return {0.0f, 0.0f};
  pcl::Indices nn(1);
  std::vector<float> d2(1);
  std::size_t inliers = 0;
  double sum = 0;
  for (const auto& q : a.points) {
    const Eigen::Vector3f p = Moved(pose, q);
    if (b.nearestKSearch(pcl::PointXYZ(p.x(), p.y(), p.z()), 1, nn, d2) != 1) continue;
    if (d2[0] > inlier_distance_m * inlier_distance_m) continue;
    ++inliers;
    sum += d2[0];
  }
  return {float(inliers) / float(a.size()),
          inliers ? float(std::sqrt(sum / double(inliers))) : 0.0f};
}

// The share of a's points, moved by `pose`, that land on a pixel where b saw its surface
// farther than them by more than `free_space_m`.
float SeenThrough(const Cloud& a, const Eigen::Matrix4f& pose, const Cloud& b, float free_space_m) {
  if (b.height <= 1) return 0;
  const auto k = EstimateIntrinsics(b);
  if (!k) return 0;
  std::size_t n = 0, through = 0;
  for (const PointT& q : a.points) {
    if (!FinitePoint(q)) continue;
    ++n;
    const Eigen::Vector3f p = (pose * q.getVector3fMap().homogeneous()).head<3>();
    if (p.z() <= 0) continue;
    const Eigen::Vector2d uv = k->Project(p);
    const long u = std::lround(uv.x()), v = std::lround(uv.y());
    if (u < 0 || v < 0 || u >= long(b.width) || v >= long(b.height)) continue;
    const PointT& s = b.at(int(u), int(v));
    through += FinitePoint(s) && p.z() < s.z - free_space_m;
  }
  return n ? float(through) / float(n) : 0.0f;
}

// How well the colours of a's overlapping points (within inlier distance of b's after `pose`)
// agree with their nearest b points': the intersection of their chromaticity histograms, as
// verification measures it; -1 when either has no colour.
float ColourAgreement(const Cloud& a, const Eigen::Matrix4f& pose, const Cloud& b,
                      const pcl::KdTreeFLANN<pcl::PointXYZ>& tree, float inlier_distance_m) {
  if (!HasColour(a) || !HasColour(b)) return -1;
  std::vector<const PointT*> b_finite;
  for (const PointT& p : b.points)
    if (FinitePoint(p)) b_finite.push_back(&p);
  pcl::Indices nn(1);
  std::vector<float> d2(1);
  ColourHistogram on_a{}, on_b{};
  for (const PointT& q : a.points) {
    if (!FinitePoint(q)) continue;
    const Eigen::Vector3f p = (pose * q.getVector3fMap().homogeneous()).head<3>();
    if (tree.nearestKSearch(pcl::PointXYZ(p.x(), p.y(), p.z()), 1, nn, d2) != 1) continue;
    if (d2[0] > inlier_distance_m * inlier_distance_m) continue;
    AddColour(q, &on_a);
    AddColour(*b_finite[std::size_t(nn[0])], &on_b);
  }
  Normalize(&on_a);
  Normalize(&on_b);
  return Intersection(on_a, on_b);
}

}  // namespace

std::pair<float, float> Overlap(const Cloud& a, const Eigen::Matrix4f& pose, const Cloud& b,
                                float inlier_distance_m) {
  const auto b_points = FiniteXyz(b);
  if (b_points->empty()) return {0.0f, 0.0f};
  pcl::KdTreeFLANN<pcl::PointXYZ> tree(false);
  tree.setInputCloud(b_points);
  return Overlap(*FiniteXyz(a), pose, tree, inlier_distance_m);
}

ViewAlignment AlignViews(const ModelDescription& a, const Cloud& b, const AlignmentOptions& o) {
  ViewAlignment out;
  SceneQuery query;
  query.foveated = false;
  RecognitionOptions recognition = o.recognition;
  recognition.table_keypoint_distance_m = 0;  // b is an object cut out: no table around it
  const RecognitionResult r = Recognize(a, b, query, recognition);
  if (r.instances.empty()) return out;
  const Detection& best = r.instances.front();
  out.confidence = best.confidence;
  out.recognized = best.model_to_scene;
  const auto b_points = FiniteXyz(b);
  if (b_points->empty()) return out;
  pcl::KdTreeFLANN<pcl::PointXYZ> tree(false);
  tree.setInputCloud(b_points);
  const auto a_points = FiniteXyz(a.cloud());
  out.pose = Icp(*a_points, tree, *b_points, best.model_to_scene, o);
  std::tie(out.overlap, out.rmse_m) = Overlap(*a_points, out.pose, tree, o.inlier_distance_m);
  out.seen_through = SeenThrough(a.cloud(), out.pose, b, o.free_space_m);
  out.colour = ColourAgreement(a.cloud(), out.pose, b, tree, o.inlier_distance_m);
  out.found = out.overlap >= o.min_overlap && out.seen_through <= o.max_seen_through &&
              (out.colour < 0 || out.colour >= o.min_colour);
  return out;
}

std::vector<std::vector<ViewAlignment>> AlignAll(const std::vector<const Cloud*>& captures,
                                                 const AlignmentOptions& options,
                                                 const ParallelFor& parallel) {
  const std::size_t n = captures.size();
  std::vector<std::optional<ModelDescription>> described(n);
  parallel(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      described[i] = DescribeModel(*captures[i], options.recognition, nullptr);
  });
  std::vector<std::vector<ViewAlignment>> pairs(n, std::vector<ViewAlignment>(n));
  parallel(n * n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const std::size_t a = k / n, b = k % n;
      if (a != b && described[a]) pairs[a][b] = AlignViews(*described[a], *captures[b], options);
    }
  });
  return pairs;
}

std::vector<Cloud> PlaceViews(const std::vector<const Cloud*>& captures,
                              const std::vector<std::optional<Eigen::Matrix4f>>& poses) {
  std::vector<Cloud> views;
  for (std::size_t i = 0; i < captures.size(); ++i) {
    if (!poses[i]) continue;
    const Eigen::Matrix4f& pose = *poses[i];
    Cloud view = *captures[i];
    for (PointT& p : view.points)
      p.getVector3fMap() = (pose * p.getVector3fMap().homogeneous()).head<3>();
    // A PCD's VIEWPOINT reads back with w = 0: the origin is a point whatever its w.
    view.sensor_origin_ =
        (pose * captures[i]->sensor_origin_.head<3>().homogeneous()).head<3>().homogeneous();
    view.sensor_orientation_ =
        Eigen::Quaternionf(pose.topLeftCorner<3, 3>()) * captures[i]->sensor_orientation_;
    views.push_back(std::move(view));
  }
  return views;
}

float LoopDisagreement(const std::vector<std::vector<ViewAlignment>>& pairs,
                       const std::vector<std::optional<Eigen::Matrix4f>>& poses,
                       const std::vector<const Cloud*>& captures) {
  float worst = 0;
  for (std::size_t a = 0; a < pairs.size(); ++a) {
    if (!poses[a]) continue;
    const auto centroid = FiniteCentroid(*captures[a]);
    if (!centroid) continue;
    const Eigen::Vector3f chained = (*poses[a] * centroid->homogeneous()).head<3>();
    for (std::size_t b = 0; b < pairs.size(); ++b) {
      if (a == b || !poses[b] || !pairs[a][b].found) continue;
      const Eigen::Vector3f direct =
          (*poses[b] * pairs[a][b].pose * centroid->homogeneous()).head<3>();
      worst = std::max(worst, (direct - chained).norm());
    }
  }
  return worst;
}

namespace {

// The alignments as undirected edges: a's pose in b's frame (from either direction's found
// alignment, the one of more overlap), and its weight: how many third captures c close the
// triangle a -> c -> b within kLoopTolerance at a's centroid, plus its overlap (under 1). A wrong
// alignment of two captures seldom agrees with two others; a right one does.
struct Edges {
  std::vector<std::vector<std::optional<Eigen::Matrix4f>>> pose;  // pose[a][b]: a into b
  std::vector<std::vector<float>> weight;                         // -1 without an edge
};

constexpr float kLoopTolerance = 0.02f;

Edges MakeEdges(const std::vector<std::vector<ViewAlignment>>& pairs,
                const std::vector<const Cloud*>& captures, const std::vector<bool>& use) {
  const std::size_t n = pairs.size();
  Edges e;
  e.pose.assign(n, std::vector<std::optional<Eigen::Matrix4f>>(n));
  e.weight.assign(n, std::vector<float>(n, -1.0f));
  std::vector<float> overlap(n * n, 0);
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < n; ++b) {
      if (a == b || !use[a] || !use[b]) continue;
      const ViewAlignment& ab = pairs[a][b];
      const ViewAlignment& ba = pairs[b][a];
      if (ab.found && (!ba.found || ab.overlap >= ba.overlap)) {
        e.pose[a][b] = ab.pose;
        overlap[a * n + b] = ab.overlap;
      } else if (ba.found) {
        e.pose[a][b] = Eigen::Matrix4f(ba.pose.inverse());
        overlap[a * n + b] = ba.overlap;
      }
    }
  }
  std::vector<Eigen::Vector3f> centroid(n, Eigen::Vector3f::Zero());
  for (std::size_t a = 0; a < n; ++a)
    if (const auto c = FiniteCentroid(*captures[a])) centroid[a] = *c;
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < n; ++b) {
      if (!e.pose[a][b]) continue;
      const Eigen::Vector3f direct = (*e.pose[a][b] * centroid[a].homogeneous()).head<3>();
      int support = 0;
      for (std::size_t c = 0; c < n; ++c) {
        if (c == a || c == b || !e.pose[a][c] || !e.pose[c][b]) continue;
        const Eigen::Vector3f via =
            (*e.pose[c][b] * *e.pose[a][c] * centroid[a].homogeneous()).head<3>();
        support += (via - direct).norm() <= kLoopTolerance;
      }
      e.weight[a][b] = float(support) + std::min(overlap[a * n + b], 0.999f);
    }
  }
  return e;
}

}  // namespace

std::vector<std::optional<Eigen::Matrix4f>> ChainViews(
    const std::vector<std::vector<ViewAlignment>>& pairs, const std::vector<const Cloud*>& captures,
    const std::vector<bool>& use, std::size_t reference, std::vector<int>* parent) {
  const std::size_t n = pairs.size();
  std::vector<std::optional<Eigen::Matrix4f>> pose(n);
  if (parent) parent->assign(n, -1);
  if (reference >= n || !use[reference]) return pose;
  const Edges edges = MakeEdges(pairs, captures, use);
  pose[reference] = Eigen::Matrix4f::Identity();
  // Prim's maximum spanning tree: each step joins the capture with the heaviest edge to one
  // already placed; a in b's frame chained with b's pose places a.
  for (;;) {
    float best = -1;
    std::size_t join = n, via = n;
    for (std::size_t a = 0; a < n; ++a) {
      if (!use[a] || pose[a]) continue;
      for (std::size_t b = 0; b < n; ++b) {
        if (!pose[b] || edges.weight[a][b] <= best) continue;
        best = edges.weight[a][b];
        join = a;
        via = b;
      }
    }
    if (join == n) break;
    pose[join] = *pose[via] * *edges.pose[join][via];
    if (parent) (*parent)[join] = int(via);
  }
  return pose;
}

std::size_t BestReference(const std::vector<std::vector<ViewAlignment>>& pairs,
                          const std::vector<const Cloud*>& captures, const std::vector<bool>& use) {
  const Edges edges = MakeEdges(pairs, captures, use);
  std::size_t best = 0;
  float best_sum = -1;
  for (std::size_t a = 0; a < pairs.size(); ++a) {
    if (!use[a]) continue;
    float sum = 0;
    for (std::size_t b = 0; b < pairs.size(); ++b) sum += std::max(0.0f, edges.weight[a][b]);
    if (sum > best_sum) {
      best_sum = sum;
      best = a;
    }
  }
  return best;
}

}  // namespace saccade
