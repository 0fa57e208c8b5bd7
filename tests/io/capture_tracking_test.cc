// Frame-to-frame tracking on real-data sequences (configs/sequences, ../shared/data): started
// from the truth of the first frame and fed only its own constant-velocity prediction (the
// last two refined poses), TrackPose follows the
// coffee can of mOSD test31 within issue 16's real-data tolerance (2 cm, 5 degrees) on every
// frame as the camera drifts, and as it circles at 0.5 m/s.
#include "core/model.h"
#include "core/sim/rerender.h"
#include "core/tracking.h"
#include "io/formats/cloud_io.h"
#include "io/sources/frame_source.h"
#include "support/test_data.h"

#include <gtest/gtest.h>

namespace saccade {
namespace {

const std::string kSourceDir = SACCADE_SOURCE_DIR;

class CaptureTracking : public ::testing::TestWithParam<const char*> {};

TEST_P(CaptureTracking, FollowsTheObjectOnEveryFrameWithinTwoCentimetresAndFiveDegrees) {
  SACCADE_REQUIRE_DATA("mosd_xcap/test/test31.pcd");
  std::string error;
  auto capture = LoadLabelledCloud(testing::DataPath("mosd_xcap/test/test31.pcd"), &error);
  ASSERT_TRUE(capture) << error;
  // The model: object 3's points, cut in the capture's frame (what `saccade segment` gives).
  Cloud model;
  for (int i : MosdObjectPoints(capture->cloud, capture->labels, 3))
    model.push_back(capture->cloud[std::size_t(i)]);
  const auto described = DescribeModel(model, RecognitionOptions{}, &error);
  ASSERT_TRUE(described) << error;
  const Eigen::Vector3f c = described->centroid();

  auto source = OpenSource(std::string("capture:") + kSourceDir + "/configs/sequences/" +
                               GetParam() + "?rate=0&data=" + testing::DataPath(""),
                           &error);
  ASSERT_TRUE(source) << error;
  Frame f;
  Eigen::Matrix4f pose = Eigen::Matrix4f::Identity(), previous = pose;
  int frames = 0;
  double worst_cm = 0, worst_deg = 0;
  while (source->Next(&f, &error) == FrameSource::Status::kFrame) {
    if (frames == 0) pose = previous = f.truth->target_pose.matrix();
    // The constant-velocity prediction: the last frame-to-frame motion applied once more.
    const Eigen::Matrix4f predicted = pose * previous.inverse() * pose;
    const TrackResult r =
        TrackPose(described->verification(), *f.cloud, f.intrinsics, predicted, TrackOptions{});
    previous = pose;
    pose = r.model_to_camera;
    const Eigen::Matrix4f truth = f.truth->target_pose.matrix();
    const Eigen::Vector3f err = (Eigen::Affine3f(pose) * c) - (Eigen::Affine3f(truth) * c);
    const Eigen::AngleAxisf turn(
        Eigen::Matrix3f(pose.topLeftCorner<3, 3>() * truth.topLeftCorner<3, 3>().transpose()));
    worst_cm = std::max(worst_cm, 100.0 * err.norm());
    worst_deg = std::max(worst_deg, double(std::abs(turn.angle())) * 180.0 / double(EIGEN_PI));
    EXPECT_LT(err.norm(), 0.02f) << GetParam() << " frame " << f.sequence;
    EXPECT_TRUE(r.tracking) << GetParam() << " frame " << f.sequence << ": fitness " << r.fitness
                            << " coverage " << r.coverage;
    ++frames;
  }
  EXPECT_EQ(frames, 90);
  EXPECT_LT(worst_deg, 5.0) << GetParam();
  std::printf("%s: worst error over %d frames %.2f cm, %.2f deg\n", GetParam(), frames, worst_cm,
              worst_deg);
}

INSTANTIATE_TEST_SUITE_P(Sequences, CaptureTracking,
                         // object-moving loses the can after about 20 frames today (issue
                         // 16's notes): it joins when tracking holds it.
                         ::testing::Values("camera-slow.yaml", "camera-fast.yaml"),
                         [](const auto& info) {
                           std::string n = info.param;
                           n = n.substr(0, n.find('.'));
                           for (char& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

}  // namespace
}  // namespace saccade
