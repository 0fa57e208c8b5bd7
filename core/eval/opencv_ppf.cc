#include "core/eval/opencv_ppf.h"

#include "core/fail.h"

#include <opencv2/core.hpp>
#include <opencv2/surface_matching.hpp>
#include <opencv2/surface_matching/ppf_helpers.hpp>

#include <chrono>

namespace saccade {

struct PpfPeerModel::Impl {
  cv::ppf_match_3d::PPF3DDetector detector;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  Impl(double sampling, double distance) : detector(sampling, distance) {}
};

PpfPeerModel::PpfPeerModel() = default;
PpfPeerModel::~PpfPeerModel() = default;
PpfPeerModel::PpfPeerModel(PpfPeerModel&&) noexcept = default;

namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The finite points as OpenCV's N x 6 float matrix (x, y, z, normal), normals from its own
// k-NN estimate, turned towards the camera at the origin.
cv::Mat WithNormals(const Cloud& cloud, int neighbors) {
  std::vector<cv::Vec3f> xyz;
  for (const PointT& p : cloud.points)
    if (p.getVector3fMap().allFinite()) xyz.emplace_back(p.x, p.y, p.z);
  cv::Mat points(int(xyz.size()), 3, CV_32F, xyz.data());
  cv::Mat out;
  if (xyz.size() < 10) return out;
  cv::ppf_match_3d::computeNormalsPC3d(points.clone(), out, neighbors, true, cv::Vec3f(0, 0, 0));
  return out;
}

}  // namespace

std::optional<PpfPeerModel> TrainPpfPeer(const Cloud& model, const PpfPeerOptions& options,
                                         std::string* error) {
  const cv::Mat points = WithNormals(model, options.normal_neighbors);
  const auto centroid = FiniteCentroid(model);
  if (points.rows < 10 || !centroid) {
    Fail(error, "the model has fewer than 10 finite points");
    return std::nullopt;
  }
  PpfPeerModel out;
  out.impl_ = std::make_unique<PpfPeerModel::Impl>(options.relative_sampling_step,
                                                   options.relative_distance_step);
  out.impl_->detector.trainModel(points);
  out.impl_->centroid = *centroid;
  return out;
}

RecognitionResult RecognizePpfPeer(const PpfPeerModel& model, const Cloud& scene,
                                   const PpfPeerOptions& options) {
  RecognitionResult result;
  const auto t_total = Clock::now();
  auto t = Clock::now();
  const cv::Mat points = WithNormals(scene, options.normal_neighbors);
  result.stats.stage_ms.emplace_back("normals", MsSince(t));
  t = Clock::now();
  std::vector<cv::ppf_match_3d::Pose3DPtr> poses;
  if (points.rows >= 10)
    // match() is not const in OpenCV (it keeps scratch state in the detector): see the header.
    const_cast<cv::ppf_match_3d::PPF3DDetector&>(model.impl().detector)
        .match(points, poses, options.relative_scene_sample_step, options.relative_distance_step);
  result.stats.stage_ms.emplace_back("match", MsSince(t));
  result.stats.hypotheses = poses.size();
  for (std::size_t i = 0; i < poses.size() && int(i) < options.instances; ++i) {
    Detection d;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) d.model_to_scene(r, c) = float(poses[i]->pose(r, c));
    d.votes = int(poses[i]->numVotes);
    d.centroid_m = (d.model_to_scene * model.impl().centroid.homogeneous()).head<3>();
    result.instances.push_back(d);
  }
  result.hypotheses = result.instances;
  result.stats.stage_ms.emplace_back("total", MsSince(t_total));
  return result;
}

}  // namespace saccade
