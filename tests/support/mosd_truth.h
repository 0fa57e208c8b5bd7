// Truth poses of the cross-capture benchmark that tests check against, copied from
// ../shared/data/mosd_xcap/cases_with_pose.yaml (row-major, model capture to scene capture).
#pragma once

#include "io/formats/cloud_io.h"

#include <Eigen/Core>

#include <cmath>
#include <utility>

namespace saccade::testing {

/// The centroid of mOSD object k's finite labelled points (labels 10k..10k+9), and how many
/// there are.
inline std::pair<Eigen::Vector3f, int> MosdObjectCentroid(const LabelledCloud& scene, int k) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (std::size_t i = 0; i < scene.labels.size(); ++i)
    if (int(scene.labels[i] / 10) == k && std::isfinite(scene.cloud[i].z))
      sum += scene.cloud[i].getVector3fMap().cast<double>(), ++n;
  return {n ? Eigen::Vector3f((sum / n).cast<float>()) : Eigen::Vector3f::Zero(), n};
}

inline Eigen::Matrix4f RowMajorPose(const float (&t)[16]) {
  return Eigen::Map<const Eigen::Matrix<float, 4, 4, Eigen::RowMajor>>(t);
}

/// coffee_can-test36-in-test38: the can (object 4) of test36 into test38's frame.
inline Eigen::Matrix4f CoffeeCanTest36InTest38() {
  const float t[16] = {0.9998525f,
                       -0.002822749f,
                       0.01691915f,
                       0.04683755f,  //
                       0.002908148f,
                       0.9999831f,
                       -0.005017745f,
                       0.04503625f,  //
                       -0.01690458f,
                       0.005066187f,
                       0.9998439f,
                       -0.06315316f,  //
                       0,
                       0,
                       0,
                       1};
  return RowMajorPose(t);
}

/// coffee_can-test36-in-learn43: the can of test36 into learn43's frame.
inline Eigen::Matrix4f CoffeeCanTest36InLearn43() {
  const float t[16] = {0.8646999f,  -0.2851199f, 0.4135228f,  -0.03086935f,  //
                       0.2728591f,  0.957848f,   0.08986289f, 0.1315799f,    //
                       -0.4217136f, 0.03512901f, 0.9060484f,  -0.226622f,    //
                       0,           0,           0,           1};
  return RowMajorPose(t);
}

}  // namespace saccade::testing
