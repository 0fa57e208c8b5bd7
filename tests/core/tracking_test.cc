// Frame-to-frame tracking on the synthetic Kinect's demo case: from seeded perturbed poses the
// refinement converges onto the true one; a pose with no object under it is not TRACKING.
#include "core/tracking.h"

#include "core/recognition.h"
#include "support/demo_case.h"

#include <gtest/gtest.h>

#include <random>

namespace saccade {
namespace {

using Demo = testing::DescribedDemo;
const Demo& TheDemo() { return testing::TheDescribedDemo(); }

TEST(TrackPose, ConvergesOntoTheTruePoseFromSeededPerturbations) {
  const Demo& d = TheDemo();
  const Eigen::Vector3f c = d.model->centroid();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> offset(-0.015f, 0.015f), angle(-4.0f, 4.0f);
  std::normal_distribution<float> axis(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector3f t(offset(rng), offset(rng), offset(rng));
    const Eigen::Vector3f a = Eigen::Vector3f(axis(rng), axis(rng), axis(rng)).normalized();
    const float deg = angle(rng);
    // The truth turned about the object's centroid and moved: up to 1.5 cm and 4 degrees off.
    const Eigen::Vector3f centre_C = d.demo.truth * c;
    const Eigen::Isometry3f perturb = Eigen::Translation3f(centre_C + t) *
                                      Eigen::AngleAxisf(deg * float(EIGEN_PI) / 180, a) *
                                      Eigen::Translation3f(-centre_C);
    const Eigen::Matrix4f start = (perturb * d.demo.truth).matrix();
    const TrackResult r =
        TrackPose(d.model->verification(), d.demo.scene.cloud, CameraIntrinsics{}, start, {});
    const PoseError e = ComparePoses(r.model_to_camera, d.demo.truth.matrix(), c);
    EXPECT_LT(e.translation_m, 0.003) << "trial " << trial;
    EXPECT_LT(e.rotation_deg, 1.5) << "trial " << trial;
    EXPECT_TRUE(r.tracking) << "trial " << trial << " fitness " << r.fitness << " coverage "
                            << r.coverage;
    EXPECT_LT(r.rms_m, 0.004f);
  }
}

TEST(TrackPose, APoseWithNoObjectUnderItIsNotTracking) {
  const Demo& d = TheDemo();
  for (const Eigen::Vector3f& away :
       {Eigen::Vector3f(0.4f, 0, 0), Eigen::Vector3f(-0.4f, 0, 0), Eigen::Vector3f(0, 0, -0.25f)}) {
    const Eigen::Matrix4f start = (Eigen::Translation3f(away) * d.demo.truth).matrix();
    const TrackResult r =
        TrackPose(d.model->verification(), d.demo.scene.cloud, CameraIntrinsics{}, start, {});
    EXPECT_FALSE(r.tracking) << away.transpose() << ": fitness " << r.fitness << " coverage "
                             << r.coverage;
  }
}

TEST(ScorePose, ScoresThePoseAsGivenAsTrackPoseScoresWhereItEnds) {
  const Demo& d = TheDemo();
  const VerificationModel& m = d.model->verification();
  const Cloud& frame = d.demo.scene.cloud;
  const TrackResult at_truth = ScorePose(m, frame, CameraIntrinsics{}, d.demo.truth.matrix(), {});
  EXPECT_TRUE(at_truth.tracking);
  EXPECT_EQ(at_truth.iterations, 0);
  const Eigen::Matrix4f off = (Eigen::Translation3f(0.01f, 0.01f, 0.01f) * d.demo.truth).matrix();
  const TrackResult as_given = ScorePose(m, frame, CameraIntrinsics{}, off, {});
  EXPECT_TRUE(as_given.model_to_camera.isApprox(off));
  EXPECT_LT(as_given.inliers, at_truth.inliers / 2);
  const TrackResult tracked = TrackPose(m, frame, CameraIntrinsics{}, off, {});
  const TrackResult rescored = ScorePose(m, frame, CameraIntrinsics{}, tracked.model_to_camera, {});
  EXPECT_EQ(rescored.inliers, tracked.inliers);
  EXPECT_EQ(rescored.facing, tracked.facing);
  EXPECT_FLOAT_EQ(rescored.fitness, tracked.fitness);
  EXPECT_GT(tracked.inliers, as_given.inliers);
}

// The demo's frame cut at `columns` pixels from the left, as a camera with a narrower image
// would see it.
struct CutFrame {
  Cloud cloud;
  CameraIntrinsics intrinsics;
};
CutFrame LeftColumns(const Cloud& frame, int columns) {
  CutFrame out;
  out.intrinsics.width = columns;  // the same pixels keep the same rays: cx stays
  for (std::uint32_t v = 0; v < frame.height; ++v)
    for (int u = 0; u < columns; ++u) out.cloud.push_back(frame.at(u, v));
  out.cloud.width = std::uint32_t(columns);  // push_back left it one row
  out.cloud.height = frame.height;
  return out;
}

TEST(TrackPose, AnObjectMostlyOutOfTheImageHasItsPositionRefinedAndItsTurnHeld) {
  const Demo& d = TheDemo();
  const Eigen::Vector3f c = d.model->centroid();
  const CameraIntrinsics full;
  const int centre_u = int(full.Project(d.demo.truth * c).x());
  // The image ends a little left of the object's centre: less than half of it is inside.
  const CutFrame cut = LeftColumns(d.demo.scene.cloud, centre_u - 10);
  const Eigen::Matrix4f turned =
      (Eigen::Translation3f(0.01f, 0, 0.005f) * d.demo.truth * Eigen::Translation3f(c) *
       Eigen::AngleAxisf(0.05f, Eigen::Vector3f::UnitY()) * Eigen::Translation3f(-c))
          .matrix();
  const TrackResult held =
      TrackPose(d.model->verification(), cut.cloud, cut.intrinsics, turned, {});
  EXPECT_TRUE(held.turn_held);
  EXPECT_LT(held.in_image, 0.5f);
  const auto turn_of = [](const Eigen::Matrix4f& m) {
    return Eigen::Matrix3f(m.topLeftCorner<3, 3>());
  };
  EXPECT_TRUE(turn_of(held.model_to_camera).isApprox(turn_of(turned)));
  EXPECT_LT(ComparePoses(held.model_to_camera, d.demo.truth.matrix(), c).translation_m,
            ComparePoses(turned, d.demo.truth.matrix(), c).translation_m / 2);

  TrackOptions always_turn;
  always_turn.min_in_image_to_turn = 0;
  const TrackResult turning =
      TrackPose(d.model->verification(), cut.cloud, cut.intrinsics, turned, always_turn);
  EXPECT_FALSE(turning.turn_held);
  EXPECT_FALSE(turn_of(turning.model_to_camera).isApprox(turn_of(turned)));

  // In the whole image the same start is turned as well as moved.
  const TrackResult whole =
      TrackPose(d.model->verification(), d.demo.scene.cloud, full, turned, {});
  EXPECT_FALSE(whole.turn_held);
  EXPECT_EQ(whole.in_image, 1.0f);
  EXPECT_LT(ComparePoses(whole.model_to_camera, d.demo.truth.matrix(), c).rotation_deg, 1.5);
}

TEST(TrackOptions, InvalidValuesNameTheField) {
  TrackOptions o;
  o.min_fitness = 2;
  std::string error;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("min_fitness"), std::string::npos) << error;
  EXPECT_TRUE(TrackOptions{}.IsValid(&error));
  o = TrackOptions{};
  o.min_in_image_to_turn = 1.5f;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("min_in_image_to_turn"), std::string::npos) << error;
}

}  // namespace
}  // namespace saccade
