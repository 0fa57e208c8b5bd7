#include "core/eval/reference_pipeline.h"

#include <pcl/features/board.h>
#include <pcl/features/normal_3d.h>
#include <pcl/features/shot.h>
#include <pcl/filters/uniform_sampling.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/recognition/cg/hough_3d.h>
#include "core/fail.h"

#include <chrono>
#include <cmath>

namespace saccade {
namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

using NormalCloud = pcl::PointCloud<pcl::Normal>;
using ShotCloud = pcl::PointCloud<pcl::SHOT352>;
using FrameCloud = pcl::PointCloud<pcl::ReferenceFrame>;

bool FiniteFrame(const pcl::ReferenceFrame& f) {
  for (float v : f.rf)
    if (!std::isfinite(v)) return false;
  return true;
}

bool FiniteShot(const pcl::SHOT352& d) { return std::isfinite(d.descriptor[0]); }

// Keypoints, descriptors and frames of one cloud with the stock stages.
struct Described {
  Cloud::Ptr keypoints{new Cloud};
  ShotCloud::Ptr shots{new ShotCloud};
  FrameCloud::Ptr frames{new FrameCloud};
};

Described Describe(const Cloud::ConstPtr& cloud, int k_normals, float keypoint_radius,
                   float shot_radius, float lrf_radius,
                   std::vector<std::pair<std::string, double>>* ms) {
  auto t = Clock::now();
  NormalCloud::Ptr normals(new NormalCloud);
  pcl::NormalEstimation<PointT, pcl::Normal> ne;
  ne.setKSearch(k_normals);
  ne.setInputCloud(cloud);
  ne.compute(*normals);
  if (ms) ms->emplace_back("normals", MsSince(t));

  t = Clock::now();
  Described d;
  pcl::UniformSampling<PointT> us;
  us.setInputCloud(cloud);
  us.setRadiusSearch(keypoint_radius);
  us.filter(*d.keypoints);
  if (ms) ms->emplace_back("keypoints", MsSince(t));

  t = Clock::now();
  pcl::SHOTEstimation<PointT, pcl::Normal, pcl::SHOT352> shot;
  shot.setRadiusSearch(shot_radius);
  shot.setInputCloud(d.keypoints);
  shot.setInputNormals(normals);
  shot.setSearchSurface(cloud);
  shot.compute(*d.shots);

  pcl::BOARDLocalReferenceFrameEstimation<PointT, pcl::Normal, pcl::ReferenceFrame> board;
  board.setFindHoles(true);
  board.setRadiusSearch(lrf_radius);
  board.setInputCloud(d.keypoints);
  board.setInputNormals(normals);
  board.setSearchSurface(cloud);
  board.compute(*d.frames);
  if (ms) ms->emplace_back("describe", MsSince(t));
  return d;
}

Cloud::Ptr FiniteCopy(const Cloud& in) {
  Cloud::Ptr out(new Cloud);
  for (const auto& p : in.points)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) out->push_back(p);
  out->width = static_cast<std::uint32_t>(out->size());
  out->height = 1;
  return out;
}

}  // namespace

struct ReferenceModel::Impl {
  Cloud::Ptr cloud;
  Described described;
  pcl::KdTreeFLANN<pcl::SHOT352> tree;
  Eigen::Vector3f centroid;
};

ReferenceModel::ReferenceModel() : impl_(std::make_unique<Impl>()) {}
ReferenceModel::~ReferenceModel() = default;
ReferenceModel::ReferenceModel(ReferenceModel&&) noexcept = default;

std::optional<ReferenceModel> DescribeReferenceModel(const Cloud& model,
                                                     const RecognitionOptions& o,
                                                     std::string* error) {
  ReferenceModel out;
  ReferenceModel::Impl& m = *out.impl_;
  m.cloud = FiniteCopy(model);
  if (m.cloud->empty()) {
    Fail(error, "model has no finite point");
    return std::nullopt;
  }
  m.described = Describe(m.cloud, o.model_normal_neighbors, o.model_keypoint_radius_m,
                         o.model_shot_radius_m, o.model_lrf_radius_m, nullptr);
  // NaN descriptors would poison the kd-tree; give them an out-of-reach value instead of
  // removing them, so indices stay aligned with keypoints and frames.
  for (auto& d : m.described.shots->points)
    if (!FiniteShot(d)) std::fill(std::begin(d.descriptor), std::end(d.descriptor), 1e6f);
  m.tree.setInputCloud(m.described.shots);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : m.cloud->points) sum += p.getVector3fMap().cast<double>();
  m.centroid = (sum / static_cast<double>(m.cloud->size())).cast<float>();
  return out;
}

RecognitionResult RecognizeReference(const ReferenceModel& model, const Cloud& scene,
                                     const RecognitionOptions& o, std::string* error) {
  RecognitionResult result;
  const auto t_total = Clock::now();
  auto t = Clock::now();
  Cloud::Ptr cloud = FiniteCopy(scene);
  result.stats.stage_ms.emplace_back("foveate", MsSince(t));
  if (cloud->empty()) {
    Fail(error, "scene has no finite point");
    return result;
  }
  const auto& m = model.impl();
  Described s = Describe(cloud, o.scene_normal_neighbors, o.scene_keypoint_radius_m,
                         o.scene_shot_radius_m, o.scene_lrf_radius_m, &result.stats.stage_ms);
  result.stats.level_points.push_back(cloud->size());
  result.stats.level_keypoints.push_back(s.keypoints->size());

  t = Clock::now();
  pcl::CorrespondencesPtr correspondences(new pcl::Correspondences);
  std::size_t described = 0;
  for (std::size_t i = 0; i < s.shots->size(); ++i) {
    // A NaN descriptor or frame never reaches matching or the Hough space.
    if (!FiniteShot((*s.shots)[i]) || !FiniteFrame((*s.frames)[i])) continue;
    ++described;
    pcl::Indices idx(1);
    std::vector<float> d2(1);
    if (m.tree.nearestKSearch((*s.shots)[i], 1, idx, d2) == 1 &&
        d2[0] < o.max_descriptor_sqr_distance && FiniteFrame((*m.described.frames)[idx[0]]))
      correspondences->emplace_back(idx[0], static_cast<int>(i), d2[0]);
  }
  result.stats.described = described;
  result.stats.correspondences = correspondences->size();
  result.stats.stage_ms.emplace_back("match", MsSince(t));

  t = Clock::now();
  pcl::Hough3DGrouping<PointT, PointT, pcl::ReferenceFrame, pcl::ReferenceFrame> hough;
  hough.setHoughBinSize(o.hough_bin_m);
  hough.setHoughThreshold(static_cast<double>(o.hough_threshold));
  hough.setUseInterpolation(true);
  hough.setUseDistanceWeight(false);
  hough.setInputCloud(m.described.keypoints);
  hough.setInputRf(m.described.frames);
  hough.setSceneCloud(s.keypoints);
  hough.setSceneRf(s.frames);
  hough.setModelSceneCorrespondences(correspondences);
  std::vector<Eigen::Matrix4f, Eigen::aligned_allocator<Eigen::Matrix4f>> poses;
  std::vector<pcl::Correspondences> clusters;
  if (!correspondences->empty()) hough.recognize(poses, clusters);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Matrix3f R = poses[i].topLeftCorner<3, 3>();
    if (!poses[i].allFinite() || std::abs(R.determinant() - 1.0f) > 1e-3f) continue;
    Detection d;
    d.model_to_scene = poses[i];
    d.votes = static_cast<int>(clusters[i].size());
    d.centroid_m = R * m.centroid + poses[i].topRightCorner<3, 1>();
    for (const auto& c : clusters[i]) d.correspondences.emplace_back(c.index_query, c.index_match);
    result.instances.push_back(std::move(d));
  }
  result.hypotheses = result.instances;  // no verification here
  result.stats.stage_ms.emplace_back("group", MsSince(t));
  result.stats.stage_ms.emplace_back("total", MsSince(t_total));
  return result;
}

}  // namespace saccade
