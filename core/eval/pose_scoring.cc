#include "core/eval/pose_scoring.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace saccade {

std::vector<Eigen::Matrix4f> CubeRotations() {
  std::vector<Eigen::Matrix4f> out;
  const int order[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& o : order)
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
      m.topLeftCorner<3, 3>().setZero();
      for (int r = 0; r < 3; ++r) m(r, o[r]) = (signs >> r) & 1 ? -1.f : 1.f;
      if (m.topLeftCorner<3, 3>().determinant() > 0) out.push_back(m);
    }
  return out;
}

PoseError LeastError(const Eigen::Matrix4f& estimate, const Eigen::Matrix4f& truth,
                     const Eigen::Matrix4f& model_in_object, const Eigen::Vector3f& centre,
                     const std::vector<Eigen::Matrix4f>& turns, Eigen::Matrix4f* matched) {
  PoseError best{0, 1e9};
  for (const Eigen::Matrix4f& turn : turns) {
    const Eigen::Matrix4f turned = truth * turn * model_in_object;
    const PoseError e = ComparePoses(estimate, turned, centre);
    if (e.rotation_deg >= best.rotation_deg) continue;
    best = e;
    if (matched) *matched = turned;
  }
  return best;
}

PoseError StepError(const Eigen::Matrix4f& pose_a, const Eigen::Matrix4f& pose_b,
                    const Eigen::Matrix4f& truth_a, const Eigen::Matrix4f& truth_b,
                    const Eigen::Vector3f& centre) {
  const auto at = [&](const Eigen::Matrix4f& m) -> Eigen::Vector3f {
    return (m * centre.homogeneous()).head<3>();
  };
  const Eigen::Vector3f shift = at(pose_b) - at(pose_a), true_shift = at(truth_b) - at(truth_a);
  const Eigen::Matrix3f turn =
      pose_b.topLeftCorner<3, 3>() * pose_a.topLeftCorner<3, 3>().transpose();
  const Eigen::Matrix3f true_turn =
      truth_b.topLeftCorner<3, 3>() * truth_a.topLeftCorner<3, 3>().transpose();
  PoseError e;
  e.translation_m = (shift - true_shift).norm();
  e.rotation_deg = Eigen::AngleAxisf(turn.transpose() * true_turn).angle() * 180.0 / M_PI;
  return e;
}

double Quantile(std::vector<double> values, double p) {
  if (values.empty()) return -1;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, std::size_t(p * double(values.size())))];
}

}  // namespace saccade
