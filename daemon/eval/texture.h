// Texture as evidence (issue 34, a measurement): ORB keypoints of the colour image, lifted to 3D
// by the registered depth, matched between a model and a scene; an instance's texture support
// is the number of matches its pose carries onto each other. The evaluation reports it beside
// each instance's figures (instances.csv) to see whether it tells look-alikes apart.
#pragma once

#include "core/camera.h"
#include "core/types.h"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace saccade::eval {

/// ORB keypoints of a cloud's colours with the 3D point under each. An organized cloud is its
/// own image; an unorganized one (a model cut from a capture, in that capture's camera frame) is
/// projected with `intrinsics` first.
class TextureView {
 public:
  TextureView(const Cloud& cloud, const CameraIntrinsics& intrinsics, int max_features);
  ~TextureView();
  TextureView(TextureView&&) noexcept;
  std::size_t size() const;

  /// Matches (model point, scene point) of `model` against this view (Hamming, ratio test).
  std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>> Match(const TextureView& model) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// How many of `matches` the pose carries within `tolerance_m` of each other.
int TextureSupport(const std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>>& matches,
                   const Eigen::Matrix4f& model_to_scene, float tolerance_m);

}  // namespace saccade::eval
