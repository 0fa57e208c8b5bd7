#include "core/model.h"

#include "core/camera.h"
#include "core/fail.h"
#include "core/foveation.h"
#include "core/nearest_within.h"
#include "core/seeded_rand.h"
#include "core/surface_views.h"
#include "core/symmetry.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <flann/flann.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <type_traits>

namespace saccade {

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
  const float shot = scale.shot_radius_m > 0 ? scale.shot_radius_m
                                             : std::max(scale.size_m / 6, 8 * scale.spacing_m);
  o.scene_shot_radius_m = o.model_shot_radius_m = shot;
  o.scene_lrf_radius_m = o.model_lrf_radius_m = 0.75f * shot;
  o.scene_keypoint_radius_m = o.model_keypoint_radius_m = std::max(shot / 4, scale.spacing_m);
  o.hough_bin_m = o.pose_inlier_threshold_m = shot / 2;
  return o;
}

ModelScale OnRadiusGrid(const ModelScale& scale, float ratio) {
  if (!(ratio > 1) || !(scale.size_m > 0)) return scale;
  const float fitted = std::max(scale.size_m / 6, 8 * scale.spacing_m);
  const float unit = 0.03f, steps = std::round(std::log(fitted / unit) / std::log(ratio));
  ModelScale out = scale;
  out.shot_radius_m = unit * std::pow(ratio, steps);
  return out;
}

RecognitionOptions RadiiForModel(const RecognitionOptions& options, const ModelScale& scale) {
  return options.radii_from_model ? FitRadii(options, scale) : options;
}

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

struct ShotIndex::Impl {
  std::vector<float> data;  // owned copy the FLANN matrix points into
  std::unique_ptr<flann::KMeansIndex<ShotL2>> kmeans;
  int checks = 0;
};

ShotIndex::ShotIndex(std::vector<float> shots, const RecognitionOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->data = std::move(shots);
  impl_->checks = options.match_checks;
  flann::Matrix<float> data(impl_->data.data(), impl_->data.size() / kShotLength, kShotLength);
  // A hierarchical k-means tree with k-means++ seeding: FLANN draws those seeds from std::rand,
  // which we seed, so the index (and every match) is the same on every run. (FLANN's
  // randomized kd-trees shuffle with std::random_device and cannot be made repeatable.)
  WithSeededRand(options.match_seed, [&] {
    impl_->kmeans = std::make_unique<flann::KMeansIndex<ShotL2>>(
        data, flann::KMeansIndexParams(options.match_branching, 11, flann::FLANN_CENTERS_KMEANSPP));
    impl_->kmeans->buildIndex();
  });
}

ShotIndex::~ShotIndex() = default;

std::pair<int, float> ShotIndex::Nearest(const float* shot, float max_sqr_distance) const {
  NearestWithin result(max_sqr_distance);
  impl_->kmeans->findNeighbors(result, shot, flann::SearchParams(impl_->checks));
  return {result.index(), result.sqr_distance()};
}

ModelDescription::~ModelDescription() = default;
ModelDescription::ModelDescription(ModelDescription&&) noexcept = default;
ModelDescription& ModelDescription::operator=(ModelDescription&&) noexcept = default;

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

namespace {

DescribeOptions ModelDescribeOptions(const RecognitionOptions& options) {
  DescribeOptions describe;
  describe.shot_radius_m = options.model_shot_radius_m;
  describe.lrf_radius_m = options.model_lrf_radius_m;
  return describe;
}

// The keypoints of a view whose SHOT support stands out of a plane by min_relief of the
// radius (RMS) or more: a flat patch of a whole surface would match every table and wall.
std::vector<int> KeypointsWithRelief(const Cloud& view, const std::vector<int>& keypoints,
                                     const NeighborSearch& search, float radius_m,
                                     float min_relief) {
  std::vector<int> out, support;
  std::vector<float> sqr_dists;
  std::vector<Eigen::Vector3f> points;
  for (int k : keypoints) {
    search.Radius(k, radius_m, &support, &sqr_dists);
    if (support.size() < 3) continue;
    points.clear();
    for (int j : support) points.push_back(view[std::size_t(j)].getVector3fMap());
    if (std::sqrt(ComputePrincipalAxes(points).variances[0]) >= min_relief * radius_m)
      out.push_back(k);
  }
  return out;
}

// A rendered mesh's point is verified only where the camera sees it at most ~75 degrees from
// face-on (the cosine).
constexpr float kMeshMinFacing = 0.25f;

// A whole surface described as a scene would show it: one side at a time, sampled on a
// camera's pixels, with the sensor's noise. Each of options.model_views views is rendered
// (RenderSurface), described as a captured model is, and its descriptors join one set, their
// keypoints moved to the surface points they lie on: one model frame, so that they vote together.
// `normals` (the surface's, either way) are turned to face the first view that saw each point,
// out of the object, hollows included; a point no view saw faces away from the centre.
Descriptors DescribeViews(const Cloud& surface, const ModelScale& scale,
                          const RecognitionOptions& options, Normals* normals) {
  const Box box = *BoundingBox(surface);
  const Eigen::Vector3f centre = (box.min + box.max) / 2;
  const CameraIntrinsics kinect;
  // Near enough for the sensor's density, far enough that the whole model is in the image.
  const float distance = ViewDistance(box.Size().norm() / 2, kinect, options.model_view_distance_m);
  const float disc = 1.5f * std::max(scale.spacing_m, 1e-4f);  // no gaps between the points
  const DescribeOptions describe = ModelDescribeOptions(options);
  Descriptors out;
  std::vector<std::uint8_t> oriented(surface.size(), 0);
  const std::vector<Eigen::Vector3f> directions = SphereDirections(options.model_views);
  for (std::size_t v = 0; v < directions.size(); ++v) {
    const Eigen::Vector3f eye = centre + distance * directions[v];
    const Eigen::Matrix4f camera = LookAt(eye, centre);
    SurfaceView view = RenderSurface(surface, *normals, kinect, camera, disc,
                                     options.model_view_noise_m, options.match_seed + unsigned(v));
    if (view.points.empty()) continue;
    for (PointT& p : view.points)  // into the model's frame, seen from the eye
      p.getVector3fMap() = (camera * p.getVector3fMap().homogeneous()).head<3>();
    view.points.sensor_origin_ = eye.homogeneous();
    const std::vector<std::uint8_t> mask(view.points.size(), 1);
    const Normals view_normals = KnnNormals(view.points, mask, options.model_normal_neighbors);
    std::vector<int> all(view.points.size());
    std::iota(all.begin(), all.end(), 0);
    const auto search = MakeKdTreeSearch(view.points, mask);
    const std::vector<int> keypoints = KeypointsWithRelief(
        view.points, VoxelRepresentatives(view.points, all, options.model_keypoint_radius_m),
        *search, describe.shot_radius_m, options.model_min_relief);
    Descriptors d = DescribeKeypoints(view.points, view_normals, keypoints, *search, describe);
    for (int& k : d.keypoint) k = view.source[std::size_t(k)];
    out.keypoint.insert(out.keypoint.end(), d.keypoint.begin(), d.keypoint.end());
    out.lrf.insert(out.lrf.end(), d.lrf.begin(), d.lrf.end());
    out.shot.insert(out.shot.end(), d.shot.begin(), d.shot.end());
    for (int i : view.source) {
      const std::size_t at = std::size_t(i);
      if (oriented[at]) continue;
      oriented[at] = 1;
      Eigen::Vector3f& n = (*normals)[at];
      if (n.dot(eye - surface[at].getVector3fMap()) < 0) n = -n;
    }
  }
  for (std::size_t i = 0; i < normals->size(); ++i) {
    Eigen::Vector3f& n = (*normals)[i];
    if (!oriented[i] && n.dot(surface[i].getVector3fMap() - centre) < 0) n = -n;
  }
  return out;
}

}  // namespace

Cloud MergeViews(const std::vector<Cloud>& views) {
  Cloud all;
  for (const Cloud& view : views)
    for (const PointT& p : view.points)
      if (FinitePoint(p)) all.push_back(p);
  return all;
}

std::optional<ModelDescription> DescribeModel(const Cloud& model, const RecognitionOptions& given,
                                              std::string* error) {
  return DescribeModel(std::vector<Cloud>{model}, given, error);
}

int ModelDescription::ViewOf(int cloud_index) const {
  if (view_starts_.size() < 2) return 0;
  const auto after = std::upper_bound(view_starts_.begin(), view_starts_.end(),
                                      std::size_t(std::max(0, cloud_index)));
  return std::clamp(int(after - view_starts_.begin()) - 1, 0, int(view_starts_.size()) - 2);
}

std::optional<ModelDescription> DescribeModel(const std::vector<Cloud>& views,
                                              const RecognitionOptions& given, std::string* error,
                                              float radius_ratio) {
  ModelDescription out;
  // Only finite points make the model; its frame and units stay those of the file. Each view's
  // points follow the previous view's: view v is [starts[v], starts[v + 1]).
  std::vector<std::size_t> starts{0};
  for (const Cloud& view : views) {
    for (const auto& p : view.points)
      if (FinitePoint(p)) out.cloud_.push_back(p);
    starts.push_back(out.cloud_.size());
  }
  if (out.cloud_.empty()) {
    Fail(error, "model has no finite point");
    return std::nullopt;
  }
  out.scale_ = OnRadiusGrid(MeasureModel(out.cloud_), radius_ratio);
  const RecognitionOptions options = RadiiForModel(given, out.scale_);
  out.cloud_.width = static_cast<std::uint32_t>(out.cloud_.size());
  out.cloud_.height = 1;
  const Box box = *BoundingBox(out.cloud_);
  if (views.size() == 1) {
    out.cloud_.sensor_origin_ = views[0].sensor_origin_;
    out.cloud_.sensor_orientation_ = views[0].sensor_orientation_;
  } else {  // seen from all around: the sensor origin inside marks it so in a file
    out.cloud_.sensor_origin_ = ((box.min + box.max) / 2).homogeneous();
  }
  out.centroid_ =
      options.vote_for_model_origin ? Eigen::Vector3f::Zero() : *FiniteCentroid(out.cloud_);

  // A single view whose sensor origin lies inside it was not captured from one place: it is a
  // whole surface (a mesh rendered from all around, `saccade model --mesh`).
  const Eigen::Vector3f origin = views[0].sensor_origin_.head<3>();
  const bool rendered = views.size() == 1 && (origin.array() > box.min.array()).all() &&
                        (origin.array() < box.max.array()).all();
  Normals normals;
  if (rendered) {
    const std::vector<std::uint8_t> mask(out.cloud_.size(), 1);
    normals = KnnNormals(out.cloud_, mask, options.model_normal_neighbors);
    out.descriptors_ = DescribeViews(out.cloud_, out.scale_, options, &normals);
  } else {
    // Captured views, each described where it was seen from (its normals face its sensor),
    // their descriptors in one index: a model seen from several sides votes in one frame.
    const DescribeOptions describe = ModelDescribeOptions(options);
    for (std::size_t v = 0; v < views.size(); ++v) {
      Cloud view;
      view.points.assign(out.cloud_.begin() + long(starts[v]),
                         out.cloud_.begin() + long(starts[v + 1]));
      if (view.empty()) continue;
      view.width = static_cast<std::uint32_t>(view.size());
      view.height = 1;
      view.sensor_origin_ = views[v].sensor_origin_;
      const std::vector<std::uint8_t> mask(view.size(), 1);
      const Normals view_normals = KnnNormals(view, mask, options.model_normal_neighbors);
      normals.insert(normals.end(), view_normals.begin(), view_normals.end());
      std::vector<int> all(view.size());
      std::iota(all.begin(), all.end(), 0);
      const std::vector<int> keypoints =
          VoxelRepresentatives(view, all, options.model_keypoint_radius_m);
      const auto search = MakeKdTreeSearch(view, mask);
      Descriptors d = DescribeKeypoints(view, view_normals, keypoints, *search, describe);
      for (int& k : d.keypoint) k += int(starts[v]);
      out.descriptors_.keypoint.insert(out.descriptors_.keypoint.end(), d.keypoint.begin(),
                                       d.keypoint.end());
      out.descriptors_.lrf.insert(out.descriptors_.lrf.end(), d.lrf.begin(), d.lrf.end());
      out.descriptors_.shot.insert(out.descriptors_.shot.end(), d.shot.begin(), d.shot.end());
    }
  }
  const bool whole_surface = rendered || views.size() > 1;
  out.verification_ = MakeVerificationModel(out.cloud_, normals, options.verify.model_points);
  out.verification_.whole_surface = whole_surface;
  if (views.size() > 1) {
    out.view_starts_ = starts;
    for (std::size_t v = 0; v < views.size(); ++v) {
      Cloud view;
      view.points.assign(out.cloud_.begin() + long(starts[v]),
                         out.cloud_.begin() + long(starts[v + 1]));
      const std::vector<Eigen::Vector3f> view_normals(normals.begin() + long(starts[v]),
                                                      normals.begin() + long(starts[v + 1]));
      out.view_verification_.push_back(
          MakeVerificationModel(view, view_normals, options.verify.model_points));
    }
  }
  if (out.descriptors_.size() == 0) {
    Fail(error, "model has no describable keypoint (too few points for the SHOT radius?)");
    return std::nullopt;
  }
  // A rendered mesh's turns onto itself, and the faces it shows edge-on, are known exactly; on
  // captured views (noisy, estimated normals) neither gained anything on the cross-capture
  // benchmark's models of other captures, and both cost (docs/RESULTS.md, "Symmetric models").
  if (rendered) {
    out.verification_.min_facing = kMeshMinFacing;
    SymmetryOptions symmetry;
    symmetry.tolerance_m = 2.5f * out.scale_.spacing_m;
    symmetry.max_sqr_distance = options.max_descriptor_sqr_distance;
    out.symmetries_ = FindSymmetries(out.cloud_, out.centroid_, out.descriptors_, symmetry);
  }
  out.index_ = std::make_unique<ShotIndex>(out.descriptors_.shot, options);
  return out;
}

}  // namespace saccade
