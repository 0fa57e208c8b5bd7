#include "core/recognition.h"

#include "core/fail.h"
#include "core/nearest_within.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <flann/flann.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <type_traits>
#include <unordered_map>

namespace saccade {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

bool PositiveFinite(float v) { return std::isfinite(v) && v > 0; }

bool FinitePoint(const PointT& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

}  // namespace

bool RecognitionOptions::IsValid(std::string* error) const {
  if (scene_normal_neighbors < 3) return Fail(error, "scene_normal_neighbors must be >= 3");
  if (model_normal_neighbors < 3) return Fail(error, "model_normal_neighbors must be >= 3");
  const std::pair<const char*, float> radii[] = {
      {"scene_keypoint_radius_m", scene_keypoint_radius_m},
      {"scene_shot_radius_m", scene_shot_radius_m},
      {"scene_lrf_radius_m", scene_lrf_radius_m},
      {"model_keypoint_radius_m", model_keypoint_radius_m},
      {"model_shot_radius_m", model_shot_radius_m},
      {"model_lrf_radius_m", model_lrf_radius_m},
      {"max_descriptor_sqr_distance", max_descriptor_sqr_distance},
      {"hough_bin_m", hough_bin_m},
      {"pose_inlier_threshold_m", pose_inlier_threshold_m},
  };
  for (const auto& [name, value] : radii)
    if (!PositiveFinite(value)) return Fail(error, std::string(name) + " must be finite and > 0");
  if (!std::isfinite(max_described_density_m) || max_described_density_m < 0)
    return Fail(error, "max_described_density_m must be finite and >= 0");
  if (hough_threshold < 1) return Fail(error, "hough_threshold must be >= 1");
  if (match_branching < 2) return Fail(error, "match_branching must be >= 2");
  if (match_checks < 1) return Fail(error, "match_checks must be >= 1");
  if (max_support_half_window_px < 0) return Fail(error, "max_support_half_window_px must be >= 0");
  if (consensus_min_votes < 3) return Fail(error, "consensus_min_votes must be >= 3");
  if (consensus_max_hypotheses < 1) return Fail(error, "consensus_max_hypotheses must be >= 1");
  return verify.IsValid(error);
}

RecognitionOptions RecognitionOptions::Paper() {
  RecognitionOptions o;
  o.radii_from_model = false;
  o.max_support_half_window_px = 0;
  o.match_branching = 16;
  o.match_checks = 32;
  return o;
}

RecognitionOptions RecognitionOptions::CrossCapture() {
  RecognitionOptions o = Paper();
  o.scene_shot_radius_m = o.model_shot_radius_m = 0.04f;
  o.scene_lrf_radius_m = o.model_lrf_radius_m = 0.03f;
  o.hough_bin_m = 0.02f;
  return o;
}

ModelScale MeasureModel(const Cloud& model) {
  ModelScale scale;
  pcl::PointCloud<pcl::PointXYZ>::Ptr points(new pcl::PointCloud<pcl::PointXYZ>);
  for (const PointT& p : model.points)
    if (FinitePoint(p)) points->push_back(pcl::PointXYZ(p.x, p.y, p.z));
  if (points->size() < 2) return scale;
  const Box box = *BoundingBox(model);
  scale.size_m = box.Size().norm();
  pcl::KdTreeFLANN<pcl::PointXYZ> tree(false);
  tree.setInputCloud(points);
  // A sample of a few thousand points gives the median spacing of a model of any size.
  const std::size_t step = std::max<std::size_t>(1, points->size() / 4000);
  std::vector<float> nearest;
  pcl::Indices nn(2);
  std::vector<float> d2(2);
  for (std::size_t i = 0; i < points->size(); i += step)
    if (tree.nearestKSearch((*points)[i], 2, nn, d2) == 2) nearest.push_back(std::sqrt(d2[1]));
  if (nearest.empty()) return scale;
  std::nth_element(nearest.begin(), nearest.begin() + nearest.size() / 2, nearest.end());
  scale.spacing_m = nearest[nearest.size() / 2];
  return scale;
}

RecognitionOptions FitRadii(const RecognitionOptions& base, const ModelScale& scale) {
  RecognitionOptions o = base;
  if (!(scale.size_m > 0)) return o;
  const float shot = std::max(scale.size_m / 6, 8 * scale.spacing_m);
  o.scene_shot_radius_m = o.model_shot_radius_m = shot;
  o.scene_lrf_radius_m = o.model_lrf_radius_m = 0.75f * shot;
  o.scene_keypoint_radius_m = o.model_keypoint_radius_m = std::max(shot / 4, scale.spacing_m);
  o.hough_bin_m = o.pose_inlier_threshold_m = shot / 2;
  return o;
}

std::vector<std::string> RecognitionOptions::IgnoredKeys() const {
  if (!radii_from_model) return {};
  return {"scene_keypoint_radius_m",
          "scene_shot_radius_m",
          "scene_lrf_radius_m",
          "model_keypoint_radius_m",
          "model_shot_radius_m",
          "model_lrf_radius_m",
          "hough_bin_m",
          "pose_inlier_threshold_m"};
}

RecognitionOptions RadiiForModel(const RecognitionOptions& options, const ModelScale& scale) {
  return options.radii_from_model ? FitRadii(options, scale) : options;
}

// ---------------------------------------------------------------------------------------------
// Model

namespace {

// Squared Euclidean distance for FLANN over SHOT descriptors. FLANN's own L2 sums into one
// accumulator, a serial chain the compiler may not vectorize (float addition does not
// reassociate); Eigen's sum keeps several partial sums in vector registers. Other element
// types (the k-means clustering's double centres) take the plain loop.
struct ShotL2 {
  typedef bool is_kdtree_distance;
  typedef float ElementType;
  typedef float ResultType;

  template <typename Iterator1, typename Iterator2>
  ResultType operator()(Iterator1 a, Iterator2 b, std::size_t size, ResultType = -1) const {
    using A = std::remove_cv_t<std::remove_pointer_t<Iterator1>>;
    using B = std::remove_cv_t<std::remove_pointer_t<Iterator2>>;
    if constexpr (std::is_pointer_v<Iterator1> && std::is_pointer_v<Iterator2> &&
                  std::is_same_v<A, float> && std::is_same_v<B, float>) {
      const Eigen::Map<const Eigen::VectorXf> va(a, Eigen::Index(size)), vb(b, Eigen::Index(size));
      return (va - vb).squaredNorm();
    } else {
      ResultType sum = 0;
      for (std::size_t i = 0; i < size; ++i) {
        const ResultType d = ResultType(a[i]) - ResultType(b[i]);
        sum += d * d;
      }
      return sum;
    }
  }
  template <typename U, typename V>
  ResultType accum_dist(const U& a, const V& b, int) const {
    return ResultType((a - b) * (a - b));
  }
};

}  // namespace

struct ModelDescription::Index {
  std::vector<float> data;  // owned copy the FLANN matrix points into
  std::unique_ptr<flann::KMeansIndex<ShotL2>> kmeans;
};

ModelDescription::~ModelDescription() = default;
ModelDescription::ModelDescription(ModelDescription&&) noexcept = default;
ModelDescription& ModelDescription::operator=(ModelDescription&&) noexcept = default;

std::pair<int, float> ModelDescription::Nearest(const float* shot, float max_sqr_distance) const {
  NearestWithin result(max_sqr_distance);
  index_->kmeans->findNeighbors(result, shot, flann::SearchParams(checks_));
  return {result.index(), result.sqr_distance()};
}

std::optional<Eigen::Vector3f> FiniteCentroid(const Cloud& cloud) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  std::size_t n = 0;
  for (const auto& p : cloud.points) {
    if (!FinitePoint(p)) continue;
    sum += p.getVector3fMap().cast<double>();
    ++n;
  }
  if (n == 0) return std::nullopt;
  return Eigen::Vector3f((sum / static_cast<double>(n)).cast<float>());
}

std::optional<ModelDescription> DescribeModel(const Cloud& model, const RecognitionOptions& given,
                                              std::string* error) {
  ModelDescription out;
  out.scale_ = MeasureModel(model);
  const RecognitionOptions options = RadiiForModel(given, out.scale_);
  // Only finite points make the model; its frame and units stay those of the file.
  for (const auto& p : model.points)
    if (FinitePoint(p)) out.cloud_.push_back(p);
  if (out.cloud_.empty()) {
    Fail(error, "model has no finite point");
    return std::nullopt;
  }
  out.cloud_.width = static_cast<std::uint32_t>(out.cloud_.size());
  out.cloud_.height = 1;
  out.cloud_.sensor_origin_ = model.sensor_origin_;
  out.cloud_.sensor_orientation_ = model.sensor_orientation_;
  out.centroid_ =
      options.vote_for_model_origin ? Eigen::Vector3f::Zero() : *FiniteCentroid(out.cloud_);

  const std::vector<std::uint8_t> mask(out.cloud_.size(), 1);
  const Normals normals = KnnNormals(out.cloud_, mask, options.model_normal_neighbors);
  out.verification_ = MakeVerificationModel(out.cloud_, normals, options.verify.model_points);
  std::vector<int> all(out.cloud_.size());
  std::iota(all.begin(), all.end(), 0);
  const std::vector<int> keypoints =
      VoxelRepresentatives(out.cloud_, all, options.model_keypoint_radius_m);
  const auto search = MakeKdTreeSearch(out.cloud_, mask);
  DescribeOptions describe;
  describe.shot_radius_m = options.model_shot_radius_m;
  describe.lrf_radius_m = options.model_lrf_radius_m;
  out.descriptors_ = DescribeKeypoints(out.cloud_, normals, keypoints, *search, describe);
  if (out.descriptors_.size() == 0) {
    Fail(error, "model has no describable keypoint (too few points for the SHOT radius?)");
    return std::nullopt;
  }
  out.index_ = std::make_unique<ModelDescription::Index>();
  out.index_->data = out.descriptors_.shot;
  flann::Matrix<float> data(out.index_->data.data(), out.descriptors_.size(), kShotLength);
  // A hierarchical k-means tree with k-means++ seeding: FLANN draws those seeds from std::rand,
  // which we seed, so the index (and every match) is the same on every run. (FLANN's
  // randomized kd-trees shuffle with std::random_device and cannot be made repeatable.)
  std::srand(options.match_seed);
  out.index_->kmeans = std::make_unique<flann::KMeansIndex<ShotL2>>(
      data, flann::KMeansIndexParams(options.match_branching, 11, flann::FLANN_CENTERS_KMEANSPP));
  out.index_->kmeans->buildIndex();
  out.checks_ = options.match_checks;
  return out;
}

// ---------------------------------------------------------------------------------------------
// Hough grouping

namespace {

struct CellKey {
  int x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    return (static_cast<std::size_t>(k.x) * 73856093u) ^
           (static_cast<std::size_t>(k.y) * 19349663u) ^
           (static_cast<std::size_t>(k.z) * 83492791u);
  }
};

// Rigid transform (no scale) taking `from` onto `to` in the least-squares sense. In double:
// GCC 12 sees a false out-of-bounds read in Eigen's float umeyama.
Eigen::Matrix4f FitRigid(const std::vector<Eigen::Vector3f>& from,
                         const std::vector<Eigen::Vector3f>& to) {
  Eigen::Matrix3Xd a(3, from.size()), b(3, to.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    a.col(i) = from[i].cast<double>();
    b.col(i) = to[i].cast<double>();
  }
  return Eigen::umeyama(a, b, false).cast<float>();
}

}  // namespace

std::vector<Detection> HoughGroup(const Descriptors& model, const Cloud& model_cloud,
                                  const Eigen::Vector3f& model_centroid, const Descriptors& scene,
                                  const Cloud& scene_cloud,
                                  const std::vector<std::pair<int, int>>& correspondences,
                                  const RecognitionOptions& options) {
  const float bin = options.hough_bin_m;
  // Each correspondence votes for where the model centroid lies in the scene: the centroid's
  // offset in the model keypoint's local frame, carried into the scene keypoint's frame.
  std::vector<Eigen::Vector3f> votes;
  std::vector<int> voter;
  for (std::size_t c = 0; c < correspondences.size(); ++c) {
    const auto [mi, si] = correspondences[c];
    const Eigen::Vector3f pm = model_cloud[model.keypoint[mi]].getVector3fMap();
    const Eigen::Vector3f ps = scene_cloud[scene.keypoint[si]].getVector3fMap();
    const Eigen::Vector3f local = model.lrf[mi] * (model_centroid - pm);
    const Eigen::Vector3f vote = ps + scene.lrf[si].transpose() * local;
    if (!vote.allFinite()) continue;
    votes.push_back(vote);
    voter.push_back(static_cast<int>(c));
  }
  // Trilinear interpolation spreads each vote over the 8 cells around it.
  std::unordered_map<CellKey, float, CellHash> acc;
  for (const auto& v : votes) {
    const Eigen::Vector3f s = v / bin - Eigen::Vector3f::Constant(0.5f);
    const Eigen::Vector3f f = s.array().floor();
    const Eigen::Vector3f t = s - f;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const float w =
              (dx ? t.x() : 1 - t.x()) * (dy ? t.y() : 1 - t.y()) * (dz ? t.z() : 1 - t.z());
          acc[{static_cast<int>(f.x()) + dx, static_cast<int>(f.y()) + dy,
               static_cast<int>(f.z()) + dz}] += w;
        }
  }
  // Peaks: cells at or over the threshold that no neighbour beats (ties go to the lower key).
  std::vector<std::pair<CellKey, float>> peaks;
  for (const auto& [key, value] : acc) {
    if (value < options.hough_threshold) continue;
    bool is_max = true;
    for (int dz = -1; dz <= 1 && is_max; ++dz)
      for (int dy = -1; dy <= 1 && is_max; ++dy)
        for (int dx = -1; dx <= 1 && is_max; ++dx) {
          if (!dx && !dy && !dz) continue;
          const CellKey n{key.x + dx, key.y + dy, key.z + dz};
          auto it = acc.find(n);
          if (it == acc.end()) continue;
          if (it->second > value ||
              (it->second == value && std::tie(n.x, n.y, n.z) < std::tie(key.x, key.y, key.z)))
            is_max = false;
        }
    if (is_max) peaks.emplace_back(key, value);
  }
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second > b.second
                                : std::tie(a.first.x, a.first.y, a.first.z) <
                                      std::tie(b.first.x, b.first.y, b.first.z);
  });

  std::vector<Detection> out;
  const float thr2 = options.pose_inlier_threshold_m * options.pose_inlier_threshold_m;
  for (const auto& [key, value] : peaks) {
    // The peak's correspondences: votes that reached its cell through the interpolation.
    const Eigen::Vector3f centre =
        (Eigen::Vector3f(key.x, key.y, key.z) + Eigen::Vector3f::Constant(0.5f)) * bin;
    std::vector<int> members;
    for (std::size_t v = 0; v < votes.size(); ++v)
      if (((votes[v] - centre).cwiseAbs().array() < bin).all()) members.push_back(voter[v]);
    if (static_cast<int>(members.size()) < 3) continue;
    Eigen::Matrix4f pose = Eigen::Matrix4f::Identity();
    // Fit, drop correspondences the fit does not explain, fit again (at most a few rounds).
    for (int round = 0; round < 4; ++round) {
      std::vector<Eigen::Vector3f> from, to;
      for (int c : members) {
        from.push_back(model_cloud[model.keypoint[correspondences[c].first]].getVector3fMap());
        to.push_back(scene_cloud[scene.keypoint[correspondences[c].second]].getVector3fMap());
      }
      pose = FitRigid(from, to);
      std::vector<int> inliers;
      for (std::size_t i = 0; i < members.size(); ++i) {
        const Eigen::Vector3f mapped =
            pose.topLeftCorner<3, 3>() * from[i] + pose.topRightCorner<3, 1>();
        if ((mapped - to[i]).squaredNorm() <= thr2) inliers.push_back(members[i]);
      }
      if (inliers.size() == members.size() || inliers.size() < 3) {
        members.swap(inliers);
        break;
      }
      members.swap(inliers);
    }
    if (static_cast<int>(members.size()) < options.hough_threshold) continue;
    if (!pose.allFinite()) continue;
    const Eigen::Matrix3f R = pose.topLeftCorner<3, 3>();
    if (std::abs(R.determinant() - 1.0f) > 1e-3f) continue;  // only proper rotations leave
    Detection d;
    d.model_to_scene = pose;
    d.votes = static_cast<int>(members.size());
    d.centroid_m = R * model_centroid + pose.topRightCorner<3, 1>();
    for (int c : members)
      d.correspondences.emplace_back(model.keypoint[correspondences[c].first],
                                     scene.keypoint[correspondences[c].second]);
    // Two peaks of one object (a split vote) are one instance: keep the stronger.
    bool duplicate = false;
    for (const Detection& kept : out)
      if ((kept.centroid_m - d.centroid_m).norm() < 2.0f * bin) duplicate = true;
    if (!duplicate) out.push_back(std::move(d));
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Detection& a, const Detection& b) { return a.votes > b.votes; });
  return out;
}

std::vector<Detection> ConsensusGroup(const Descriptors& model, const Cloud& model_cloud,
                                      const Eigen::Vector3f& model_centroid,
                                      const Descriptors& scene, const Cloud& scene_cloud,
                                      const std::vector<std::pair<int, int>>& correspondences,
                                      const RecognitionOptions& options) {
  const std::size_t n = correspondences.size();
  std::vector<Eigen::Vector3f> from(n), to(n);
  std::vector<Eigen::Matrix4f> pose(n, Eigen::Matrix4f::Identity());
  for (std::size_t c = 0; c < n; ++c) {
    const auto [mi, si] = correspondences[c];
    from[c] = model_cloud[model.keypoint[mi]].getVector3fMap();
    to[c] = scene_cloud[scene.keypoint[si]].getVector3fMap();
    // The two local frames give the whole pose: rotation R = L_s^T L_m, then the keypoints meet.
    const Eigen::Matrix3f R = scene.lrf[si].transpose() * model.lrf[mi];
    pose[c].topLeftCorner<3, 3>() = R;
    pose[c].topRightCorner<3, 1>() = to[c] - R * from[c];
  }
  const float thr2 = options.pose_inlier_threshold_m * options.pose_inlier_threshold_m;
  const auto agreeing = [&](const Eigen::Matrix4f& p) {
    std::vector<int> members;
    const Eigen::Matrix3f R = p.topLeftCorner<3, 3>();
    const Eigen::Vector3f t = p.topRightCorner<3, 1>();
    for (std::size_t c = 0; c < n; ++c)
      if ((R * from[c] + t - to[c]).squaredNorm() <= thr2) members.push_back(int(c));
    return members;
  };
  std::vector<int> support(n, 0);
  for (std::size_t c = 0; c < n; ++c)
    if (pose[c].allFinite()) support[c] = int(agreeing(pose[c]).size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return support[a] > support[b]; });
  std::vector<std::uint8_t> used(n, 0);
  std::vector<Detection> out;
  for (int seed : order) {
    if (support[seed] < options.consensus_min_votes ||
        int(out.size()) >= options.consensus_max_hypotheses)
      break;
    if (used[seed]) continue;
    // Refit on the seed's agreeing matches, re-gather, twice: the seed's own frames are noisy.
    Eigen::Matrix4f p = pose[seed];
    std::vector<int> members = agreeing(p);
    for (int round = 0; round < 2 && int(members.size()) >= 3; ++round) {
      std::vector<Eigen::Vector3f> a, b;
      for (int c : members) a.push_back(from[c]), b.push_back(to[c]);
      const Eigen::Matrix4f refit = FitRigid(a, b);
      if (!refit.allFinite()) break;
      std::vector<int> again = agreeing(refit);
      if (again.size() < members.size()) break;
      p = refit;
      members.swap(again);
    }
    for (int c : members) used[c] = 1;
    used[seed] = 1;
    if (int(members.size()) < options.consensus_min_votes) continue;
    const Eigen::Matrix3f R = p.topLeftCorner<3, 3>();
    if (std::abs(R.determinant() - 1.0f) > 1e-3f) continue;
    Detection d;
    d.model_to_scene = p;
    d.votes = int(members.size());
    d.centroid_m = R * model_centroid + p.topRightCorner<3, 1>();
    for (int c : members)
      d.correspondences.emplace_back(model.keypoint[correspondences[c].first],
                                     scene.keypoint[correspondences[c].second]);
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<Detection> MergeHypotheses(std::vector<Detection> a, std::vector<Detection> b,
                                       float min_separation_m) {
  for (Detection& d : b) {
    const bool duplicate = std::any_of(a.begin(), a.end(), [&](const Detection& k) {
      return (k.centroid_m - d.centroid_m).norm() < min_separation_m;
    });
    if (!duplicate) a.push_back(std::move(d));
  }
  std::stable_sort(a.begin(), a.end(),
                   [](const Detection& x, const Detection& y) { return x.votes > y.votes; });
  return a;
}

// ---------------------------------------------------------------------------------------------
// Scene

std::size_t RecognitionStats::TotalPoints() const {
  return std::accumulate(level_points.begin(), level_points.end(), std::size_t{0});
}
std::size_t RecognitionStats::TotalKeypoints() const {
  return std::accumulate(level_keypoints.begin(), level_keypoints.end(), std::size_t{0});
}

RecognitionResult Recognize(const ModelDescription& model, const Cloud& scene,
                            const SceneQuery& query, const RecognitionOptions& given,
                            const ParallelFor& parallel_for, std::string* error) {
  const RecognitionOptions options = RadiiForModel(given, model.scale());
  RecognitionResult result;
  auto& stats = result.stats;
  const auto t_total = Clock::now();
  auto t = Clock::now();

  // 1. Which points to keep, per level, and with which keypoint radius. Only the levels fine
  // enough to describe are computed: the periphery's points would never be used.
  std::optional<CameraIntrinsics> intrinsics = query.intrinsics;
  if (!intrinsics && scene.height > 1) intrinsics = EstimateIntrinsics(scene);
  const bool organized = intrinsics.has_value() && scene.height > 1;
  std::vector<std::vector<int>> level_points;  // indices into `scene`
  std::vector<float> level_radius;
  if (query.foveated) {
    const auto bounds = BoundingBox(scene);
    if (!bounds) {
      Fail(error, "scene has no finite point");
      return result;
    }
    const FoveaGeometry geometry = ComputeFoveaGeometry(query.fovea, *bounds, query.fovea_m);
    int first = query.fovea.finest_level;
    while (first > 0 && LevelDensity(query.fovea, first - 1) <= options.max_described_density_m)
      --first;
    level_points =
        FoveateIndices(scene, query.fovea, geometry, first, organized ? &*intrinsics : nullptr);
    for (int k = 0; k <= query.fovea.finest_level; ++k)
      level_radius.push_back(LevelKeypointRadius(query.fovea, k));
    result.fovea = geometry;
  } else {
    level_points.emplace_back();
    for (int i = 0, n = static_cast<int>(scene.size()); i < n; ++i)
      if (FinitePoint(scene[i])) level_points.back().push_back(i);
    if (level_points.back().empty()) {
      Fail(error, "scene has no finite point");
      return result;
    }
    level_radius.push_back(options.scene_keypoint_radius_m);
  }
  std::vector<std::uint8_t> mask(scene.size(), 0);
  for (const auto& level : level_points)
    for (int i : level) mask[i] = 1;
  for (const auto& level : level_points) stats.level_points.push_back(level.size());
  stats.stage_ms.emplace_back("foveate", MsSince(t));

  // 2. Keypoints per level, each with its own radius.
  t = Clock::now();
  std::vector<int> keypoints;
  for (std::size_t k = 0; k < level_points.size(); ++k) {
    const auto kp = VoxelRepresentatives(scene, level_points[k], level_radius[k]);
    stats.level_keypoints.push_back(kp.size());
    keypoints.insert(keypoints.end(), kp.begin(), kp.end());
  }
  stats.stage_ms.emplace_back("keypoints", MsSince(t));

  // 3. SHOT with its local frame, on the kept points as the search surface, and the normals
  // they read, from the full-resolution geometry. With sampled supports (a bounded number of
  // points each) the supports are found first and normals computed only where they read them:
  // a fraction of the kept points. Unsampled supports read nearly every kept point, and held
  // in memory they would run to hundreds of megabytes on a whole frame: there every kept
  // point gets its normal and each support is found as it is described.
  const auto search =
      organized ? MakeOrganizedSearch(scene, *intrinsics, mask, options.max_support_half_window_px)
                : MakeKdTreeSearch(scene, mask);
  DescribeOptions describe;
  describe.shot_radius_m = options.scene_shot_radius_m;
  describe.lrf_radius_m = options.scene_lrf_radius_m;
  const auto normals_on = [&](const std::vector<std::uint8_t>& where) {
    return organized ? OrganizedNormals(scene, *intrinsics, where, options.scene_normal_neighbors,
                                        parallel_for)
                     : KnnNormals(scene, where, options.scene_normal_neighbors);
  };
  Descriptors scene_desc;
  if (organized && options.max_support_half_window_px > 0) {
    t = Clock::now();
    const Supports supports = FindSupports(scene, keypoints, *search, describe, parallel_for);
    const double ms_supports = MsSince(t);
    t = Clock::now();
    const Normals normals = normals_on(SupportMask(supports, scene.size()));
    stats.stage_ms.emplace_back("normals", MsSince(t));
    t = Clock::now();
    scene_desc = DescribeKeypoints(scene, normals, keypoints, supports, describe, parallel_for);
    stats.stage_ms.emplace_back("describe", ms_supports + MsSince(t));
  } else {
    t = Clock::now();
    const Normals normals = normals_on(mask);
    stats.stage_ms.emplace_back("normals", MsSince(t));
    t = Clock::now();
    scene_desc = DescribeKeypoints(scene, normals, keypoints, *search, describe, parallel_for);
    stats.stage_ms.emplace_back("describe", MsSince(t));
  }
  stats.described = scene_desc.size();

  // 4. Nearest model descriptor of each scene descriptor.
  t = Clock::now();
  std::vector<std::pair<int, float>> nearest(scene_desc.size());
  parallel_for(scene_desc.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      nearest[i] = model.Nearest(scene_desc.Row(i), options.max_descriptor_sqr_distance);
  });
  std::vector<std::pair<int, int>> correspondences;
  for (std::size_t i = 0; i < nearest.size(); ++i)
    if (nearest[i].first >= 0 && nearest[i].second < options.max_descriptor_sqr_distance)
      correspondences.emplace_back(nearest[i].first, static_cast<int>(i));
  stats.correspondences = correspondences.size();
  for (const auto& [m, d] : correspondences)
    result.correspondences.emplace_back(model.descriptors().keypoint[m], scene_desc.keypoint[d]);
  stats.stage_ms.emplace_back("match", MsSince(t));

  // 5. Hough voting and pose per instance.
  t = Clock::now();
  result.instances = HoughGroup(model.descriptors(), model.cloud(), model.centroid(), scene_desc,
                                scene, correspondences, options);
  if (options.consensus_grouping)
    result.instances =
        MergeHypotheses(std::move(result.instances),
                        ConsensusGroup(model.descriptors(), model.cloud(), model.centroid(),
                                       scene_desc, scene, correspondences, options),
                        2.0f * options.hough_bin_m);
  stats.hypotheses = result.instances.size();
  result.hypotheses = result.instances;
  stats.stage_ms.emplace_back("group", MsSince(t));

  // 6. Keep the hypotheses the scene confirms, refined.
  t = Clock::now();
  if (options.verify.enabled)
    result.instances = VerifyInstances(
        model.verification(), model.centroid(), scene, organized ? intrinsics : std::nullopt,
        std::move(result.instances), options.verify, parallel_for, &result.verdicts);
  stats.stage_ms.emplace_back("verify", MsSince(t));
  stats.stage_ms.emplace_back("total", MsSince(t_total));
  return result;
}

PoseError ComparePoses(const Eigen::Matrix4f& estimate, const Eigen::Matrix4f& truth,
                       const Eigen::Vector3f& model_point) {
  const Eigen::Affine3d e(estimate.cast<double>()), g(truth.cast<double>());
  PoseError err;
  err.translation_m = (e * model_point.cast<double>() - g * model_point.cast<double>()).norm();
  const Eigen::Matrix3d dR = e.linear().transpose() * g.linear();
  const double c = std::clamp((dR.trace() - 1.0) / 2.0, -1.0, 1.0);
  err.rotation_deg = std::acos(c) * 180.0 / M_PI;
  return err;
}

}  // namespace saccade
