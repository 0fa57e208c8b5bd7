#include "daemon/eval/texture.h"

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <cmath>
#include <limits>

namespace saccade::eval {

struct TextureView::Impl {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  std::vector<Eigen::Vector3f> points;  // under each keypoint
};

TextureView::TextureView(const Cloud& cloud, const CameraIntrinsics& k, int max_features)
    : impl_(std::make_unique<Impl>()) {
  const int w = k.width, h = k.height;
  cv::Mat grey(h, w, CV_8UC1, cv::Scalar(0)), mask(h, w, CV_8UC1, cv::Scalar(0));
  std::vector<Eigen::Vector3f> at(
      std::size_t(w) * std::size_t(h),
      Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  const bool organized = cloud.isOrganized() && int(cloud.width) == w && int(cloud.height) == h;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointT& p = cloud[i];
    if (!FinitePoint(p) || p.z <= 0) continue;
    int u, v;
    if (organized) {
      u = int(i % cloud.width), v = int(i / cloud.width);
    } else {
      const Eigen::Vector2d px = k.Project(p.getVector3fMap());
      u = int(std::lround(px.x())), v = int(std::lround(px.y()));
      if (u < 0 || v < 0 || u >= w || v >= h) continue;
    }
    grey.at<std::uint8_t>(v, u) = std::uint8_t((77 * p.r + 150 * p.g + 29 * p.b) >> 8);
    mask.at<std::uint8_t>(v, u) = 255;
    at[std::size_t(v) * std::size_t(w) + std::size_t(u)] = p.getVector3fMap();
  }
  cv::Ptr<cv::ORB> orb = cv::ORB::create(max_features);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  orb->detectAndCompute(grey, mask, keypoints, descriptors);
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const int u = int(std::lround(keypoints[i].pt.x)), v = int(std::lround(keypoints[i].pt.y));
    if (u < 0 || v < 0 || u >= w || v >= h) continue;
    const Eigen::Vector3f& p = at[std::size_t(v) * std::size_t(w) + std::size_t(u)];
    if (!p.allFinite()) continue;
    impl_->keypoints.push_back(keypoints[i]);
    impl_->descriptors.push_back(descriptors.row(int(i)));
    impl_->points.push_back(p);
  }
}

TextureView::~TextureView() = default;
TextureView::TextureView(TextureView&&) noexcept = default;
std::size_t TextureView::size() const { return impl_->points.size(); }

std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>> TextureView::Match(
    const TextureView& model) const {
  std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>> out;
  if (model.impl_->descriptors.empty() || impl_->descriptors.empty()) return out;
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(model.impl_->descriptors, impl_->descriptors, knn, 2);
  for (const auto& m : knn) {
    if (m.size() < 2 || m[0].distance >= 0.8f * m[1].distance) continue;
    out.emplace_back(model.impl_->points[std::size_t(m[0].queryIdx)],
                     impl_->points[std::size_t(m[0].trainIdx)]);
  }
  return out;
}

int TextureSupport(const std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>>& matches,
                   const Eigen::Matrix4f& model_to_scene, float tolerance_m) {
  int n = 0;
  for (const auto& [m, s] : matches)
    n += ((model_to_scene * m.homogeneous()).head<3>() - s).norm() <= tolerance_m;
  return n;
}

}  // namespace saccade::eval
