// Overlays drawn into an RGB image (core/pictures/overlay.h): geometry on hand-made inputs, and the
// milk carton drawn at its true pose over the real Kinect scene (../shared/data) covering the
// carton.
#include "core/pictures/overlay.h"

#include "core/features.h"
#include "core/types.h"
#include "io/formats/cloud_io.h"
#include "support/test_data.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <random>

namespace saccade {
namespace {

constexpr Rgb kBlue{0, 0, 255};
constexpr Rgb kWhite{255, 255, 255};

int CountColour(const RgbCanvas& canvas, Rgb colour) {
  int n = 0;
  for (int v = 0; v < canvas.height; ++v)
    for (int u = 0; u < canvas.width; ++u) n += canvas.At(u, v) == colour;
  return n;
}

TEST(OrientedBox, FitsARotatedBoxOfPointsOverSeededRotations) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1, 1);
  const Eigen::Vector3f half(0.10f, 0.05f, 0.02f);  // three distinct extents: unique axes
  const auto rotation = [&] {
    return Eigen::Quaternionf(unit(rng), unit(rng), unit(rng), unit(rng)).normalized();
  };
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Quaternionf q = rotation();
    const Eigen::Vector3f centre(unit(rng), unit(rng), 1 + unit(rng));
    // A regular grid over the box, symmetric about each of its axes: its principal axes are
    // the box's, so the box that holds it is the box itself.
    std::vector<Eigen::Vector3f> points;
    for (int i = 0; i < 125; ++i) {
      const Eigen::Vector3f step(i % 5 - 2, (i / 5) % 5 - 2, i / 25 - 2);  // -2..2 each
      points.push_back(centre + q * half.cwiseProduct(step / 2));
    }
    const OrientedBox box = FitOrientedBox(points);
    EXPECT_TRUE((box.centre_m - centre).isZero(1e-4f)) << trial;
    Eigen::Vector3f sorted = box.half_size_m;
    std::sort(sorted.data(), sorted.data() + 3);
    EXPECT_TRUE(sorted.isApprox(Eigen::Vector3f(0.02f, 0.05f, 0.10f), 1e-3f)) << sorted.transpose();
    EXPECT_NEAR(box.axes.determinant(), 1.0f, 1e-4f);
    // Whatever the points, the box holds each of them.
    std::vector<Eigen::Vector3f> cloud;
    for (int i = 0; i < 300; ++i)
      cloud.push_back(centre +
                      q * half.cwiseProduct(Eigen::Vector3f(unit(rng), unit(rng), unit(rng))));
    const OrientedBox around = FitOrientedBox(cloud);
    for (const Eigen::Vector3f& p : cloud) {
      const Eigen::Vector3f local = around.axes.transpose() * (p - around.centre_m);
      EXPECT_TRUE((local.cwiseAbs().array() <= around.half_size_m.array() + 1e-5f).all());
    }
    // Moved by a pose, the box's corners are the moved corners.
    Eigen::Matrix4f X = Eigen::Matrix4f::Identity();
    X.topLeftCorner<3, 3>() = rotation().toRotationMatrix();
    X.topRightCorner<3, 1>() = Eigen::Vector3f(unit(rng), unit(rng), unit(rng));
    const auto moved = box.Transformed(X).Corners();
    const auto corners = box.Corners();
    for (int i = 0; i < 8; ++i)
      EXPECT_TRUE(moved[i].isApprox(X.topLeftCorner<3, 3>() * corners[i] + X.topRightCorner<3, 1>(),
                                    1e-4f));
  }
}

TEST(SceneImage, AnUnorganizedCloudLandsWhereItsPointsProjectAndTheNearestWins) {
  const CameraIntrinsics camera;
  Cloud cloud;
  const auto add = [&](double u, double v, double z, std::uint8_t r) {
    PointT p;
    p.getVector3fMap() = camera.Unproject(u, v, z);
    p.r = r, p.g = 0, p.b = 0, p.a = 255;
    cloud.push_back(p);
  };
  add(100, 50, 2.0, 10);
  add(100, 50, 1.0, 20);  // nearer, at the same pixel
  add(600, 400, 1.5, 30);
  const RgbCanvas image = SceneImage(cloud, camera);
  ASSERT_EQ(image.width, 640);
  ASSERT_EQ(image.height, 480);
  EXPECT_EQ(image.At(100, 50), (Rgb{20, 0, 0}));
  EXPECT_EQ(image.At(600, 400), (Rgb{30, 0, 0}));
  EXPECT_EQ(CountColour(image, Rgb{}), 640 * 480 - 2);
}

// The preview's image (core/pictures/preview.cc): an organized cloud decimated by `step` keeps
// pixel (u step, v step) as its (u, v), coloured or shaded by depth.
TEST(SceneImage, AStepKeepsEveryStepthPixelOfAnOrganizedCloud) {
  Cloud cloud(7, 5);  // 7 x 5: step 2 gives 3 x 2, the odd column and row dropped
  for (int v = 0; v < 5; ++v)
    for (int u = 0; u < 7; ++u) {
      PointT& p = cloud.at(u, v);
      p.x = 0.01f * u, p.y = 0.01f * v, p.z = 1.0f + 0.1f * (u + 7 * v);
      p.r = static_cast<std::uint8_t>(10 * u), p.g = static_cast<std::uint8_t>(10 * v), p.b = 1;
      p.a = 255;
    }
  const RgbCanvas image = SceneImage(cloud, CameraIntrinsics{}, 2);
  ASSERT_EQ(image.width, 3);
  ASSERT_EQ(image.height, 2);
  for (int v = 0; v < 2; ++v)
    for (int u = 0; u < 3; ++u)
      EXPECT_EQ(image.At(u, v),
                (Rgb{static_cast<std::uint8_t>(20 * u), static_cast<std::uint8_t>(20 * v), 1}))
          << u << "," << v;
  // Without colour: shaded by depth, the nearest kept point (the cloud's first) brightest.
  for (PointT& p : cloud.points) p.r = p.g = p.b = 0;
  const RgbCanvas shaded = SceneImage(cloud, CameraIntrinsics{}, 2);
  ASSERT_EQ(shaded.width, 3);
  EXPECT_GT(shaded.At(0, 0).r, shaded.At(2, 1).r);
  EXPECT_GT(shaded.At(2, 0).r, shaded.At(2, 1).r);
}

// A model drawn from four sides: a red square 2 cm in front of a blue one (seen first from -z,
// where a camera at the origin stands): the first panel shows red in its centre over the blue,
// the third (from behind) blue; each panel draws something and only inside itself.
TEST(ModelImage, DrawsTheModelFromFourSidesNearerPointsOverFartherOnes) {
  Cloud model;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j)
      for (const float z : {0.49f, 0.51f}) {
        PointT p;
        p.x = 0.001f * float(i);
        p.y = 0.001f * float(j);
        p.z = z;
        p.r = z < 0.5f ? 255 : 0;
        p.g = 0;
        p.b = z < 0.5f ? 0 : 255;
        p.a = 255;
        model.push_back(p);
      }
  model.sensor_origin_ = Eigen::Vector4f(0, 0, 0, 1);
  const int panel = 200;
  const RgbCanvas image = ModelImage(model, 4, panel);
  ASSERT_EQ(image.width, 4 * panel);
  ASSERT_EQ(image.height, panel);
  const auto centre = [&](int k) { return image.At(k * panel + panel / 2, panel / 2); };
  EXPECT_GT(centre(0).r, 100);
  EXPECT_EQ(centre(0).b, 0);
  EXPECT_GT(centre(2).b, 100);
  EXPECT_EQ(centre(2).r, 0);
  for (int k = 0; k < 4; ++k) {
    int drawn = 0;
    for (int v = 0; v < panel; ++v)
      for (int u = panel / 4; u < panel; ++u) drawn += image.At(k * panel + u, v) != kWhite;
    EXPECT_GT(drawn, 100) << "panel " << k;
  }
}

TEST(Drawing, LinesFarOutsideTheImageAreClippedAndTextStaysInItsBox) {
  RgbCanvas canvas(64, 48, kWhite);
  // A line from far away across the image: drawn where it crosses, nothing else, at once.
  DrawLine({-1e9, 10}, {1e9, 10}, kBlue, 1, &canvas);
  EXPECT_EQ(CountColour(canvas, kBlue), 64);
  for (int u = 0; u < 64; ++u) EXPECT_EQ(canvas.At(u, 10), kBlue);
  // Behind the camera: nothing.
  DrawSegment({0, 0, -1}, {0.1f, 0, -2}, CameraIntrinsics{}, kBlue, 1, &canvas);
  EXPECT_EQ(CountColour(canvas, kBlue), 64);

  RgbCanvas text(64, 48, kWhite);
  DrawText("#0 0.93", 4, 20, 1, kBlue, Rgb{}, &text);
  const Eigen::Vector2i size = TextSize("#0 0.93", 1);
  EXPECT_EQ(size, Eigen::Vector2i(7 * 6 - 1, 7));
  int inked = 0;
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u) {
      const bool in_box = u >= 3 && u <= 4 + size.x() && v >= 19 && v <= 20 + size.y();
      if (!in_box) {
        EXPECT_EQ(text.At(u, v), kWhite) << u << "," << v;
      }
      inked += text.At(u, v) == kBlue;
    }
  EXPECT_GT(inked, 30);  // the glyphs are there, not only their background
}

// The milk carton's model drawn at its true pose over the real scene: the pixels its points
// project to are the overlay's colour, and pixels well away from it are the scene's.
TEST(Overlay, MilkCartonAtItsTruePoseCoversTheCartonAndNothingFarFromIt) {
  SACCADE_REQUIRE_DATA("pcl_test/milk_cartoon_all_small_clorox.pcd");
  std::string error;
  const auto scene =
      LoadCloud(testing::DataPath("pcl_test/milk_cartoon_all_small_clorox.pcd"), &error);
  ASSERT_TRUE(scene) << error;
  const auto model =
      LoadCloud(testing::DataPath("pcl_data/correspondence_grouping/milk.pcd"), &error);
  ASSERT_TRUE(model) << error;
  const auto truth = LoadPose(
      testing::DataPath("pcl_data/correspondence_grouping/milk_pose_in_scene.txt"), &error);
  ASSERT_TRUE(truth) << error;
  const auto camera = EstimateIntrinsics(*scene);
  ASSERT_TRUE(camera);

  std::vector<Eigen::Vector3f> model_M;
  for (const PointT& p : model->points)
    if (FinitePoint(p)) model_M.push_back(p.getVector3fMap());
  const RgbCanvas before = SceneImage(*scene, *camera);
  ASSERT_EQ(before.width, 640);
  ASSERT_EQ(before.height, 480);
  const Rgb kMark{255, 0, 255};
  ASSERT_EQ(CountColour(before, kMark), 0) << "the scene itself has the overlay's colour";
  RgbCanvas after = before;
  DrawMarks(model_M, FitOrientedBox(model_M), {{*truth, kMark, "#0 0.97"}}, *camera, &after);

  // Where the carton is: the scene's own points of it (milk.pcd's points lie on the scene's,
  // so their pixels are the carton's), and their 2D box.
  const Eigen::Matrix3f R = truth->topLeftCorner<3, 3>();
  const Eigen::Vector3f t = truth->topRightCorner<3, 1>();
  Eigen::Vector2i lo(1 << 20, 1 << 20), hi(-1, -1);
  int covered = 0, seen = 0;
  for (const Eigen::Vector3f& p : model_M) {
    const Eigen::Vector2d uv = camera->Project(R * p + t);
    const Eigen::Vector2i px(static_cast<int>(std::lround(uv.x())),
                             static_cast<int>(std::lround(uv.y())));
    if (!after.Inside(px.x(), px.y())) continue;
    ++seen;
    covered += after.At(px.x(), px.y()) == kMark;
    lo = lo.cwiseMin(px);
    hi = hi.cwiseMax(px);
  }
  ASSERT_GT(seen, 10000);
  EXPECT_GE(covered, 0.9 * seen) << covered << " of " << seen << " carton pixels covered";
  // The carton's box in the image is tens of pixels across, at the carton (its centroid,
  // camera frame (-0.056, -0.127, 0.776) m, lands near pixel (282, 154)).
  EXPECT_GT(hi.x() - lo.x(), 40);
  EXPECT_GT(hi.y() - lo.y(), 60);
  const Eigen::Vector2d centre = camera->Project(Eigen::Vector3f(-0.056f, -0.127f, 0.776f));
  EXPECT_TRUE(centre.x() > lo.x() && centre.x() < hi.x() && centre.y() > lo.y() &&
              centre.y() < hi.y());
  // Far from it (40 pixels beyond its box: room for the box's lines and the label), every
  // pixel is unchanged; near it, some changed.
  int far = 0, changed_far = 0, changed = 0;
  for (int v = 0; v < after.height; ++v)
    for (int u = 0; u < after.width; ++u) {
      const bool differs = after.At(u, v) != before.At(u, v);
      changed += differs;
      if (u < lo.x() - 40 || u > hi.x() + 40 || v < lo.y() - 40 || v > hi.y() + 40) {
        ++far;
        changed_far += differs;
      }
    }
  EXPECT_GT(far, 200000);
  EXPECT_EQ(changed_far, 0);
  EXPECT_GE(changed, covered);
}

}  // namespace
}  // namespace saccade
