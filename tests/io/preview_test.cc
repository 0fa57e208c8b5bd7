// The preview (core/pictures/preview.h) and its wire form (io/lcm/preview.h): what a viewer gets
// back is what was made, it fits max_bytes, and a malformed message is refused, never trusted.
#include "core/pictures/preview.h"
#include "core/foveation.h"
#include "io/lcm/preview.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace saccade {
namespace {

// A 640x480 frame of a slanted, textured wall 1-2 m away, and a 10 cm cube model.
struct Scene {
  Cloud cloud;
  CameraIntrinsics intrinsics;
  Cloud model;
  Scene() {
    cloud.width = 640;
    cloud.height = 480;
    cloud.resize(640 * 480);
    std::mt19937 rng(7);
    for (int v = 0; v < 480; ++v)
      for (int u = 0; u < 640; ++u) {
        const double z = 1.0 + u / 640.0;
        PointT& p = cloud.at(u, v);
        p.getVector3fMap() = intrinsics.Unproject(u, v, z);
        p.r = static_cast<std::uint8_t>(rng() % 256), p.g = 90, p.b = 40;
      }
    for (int i = 0; i < 1000; ++i) {
      PointT p;
      p.x = (i % 10) * 0.01f, p.y = (i / 10 % 10) * 0.01f, p.z = (i / 100) * 0.01f;
      model.push_back(p);
    }
  }
};

Preview MakeOne(const Scene& s, const PreviewOptions& options, FoveaGeometry* geometry) {
  FoveaOptions fovea;
  *geometry = ComputeFoveaGeometry(fovea, *BoundingBox(s.cloud), Eigen::Vector3f(0, 0, 1.5f));
  Detection d;
  d.model = 0;
  d.model_to_scene.block<3, 1>(0, 3) = Eigen::Vector3f(0.1f, 0.05f, 1.4f);
  d.centroid_m = Eigen::Vector3f(0.145f, 0.095f, 1.445f);
  const Cloud* model = &s.model;
  Preview p = MakePreview(s.cloud, s.intrinsics, *geometry, {d}, {model}, options);
  p.seq = 42;
  p.fovea_m = Eigen::Vector3f(0, 0, 1.5f);
  p.has_truth = true;
  p.truth_centroid_m = Eigen::Vector3f(0.14f, 0.1f, 1.44f);
  return p;
}

TEST(Preview, RoundTripsUnderSixtyKilobytesWithEveryPartAViewerDraws) {
  const Scene s;
  PreviewOptions options;
  FoveaGeometry geometry;
  const Preview p = MakeOne(s, options, &geometry);
  EXPECT_EQ(p.intrinsics.width, 320);
  EXPECT_EQ(p.intrinsics.height, 240);
  EXPECT_DOUBLE_EQ(p.intrinsics.fx, s.intrinsics.fx / 2);
  EXPECT_TRUE(p.colour);
  EXPECT_LE(p.levels.size(), static_cast<std::size_t>(options.max_points));
  EXPECT_GT(p.levels.size(), 1000u);
  EXPECT_LE(p.instance_of_point.size(), static_cast<std::size_t>(options.model_points));
  EXPECT_GT(p.instance_of_point.size(), static_cast<std::size_t>(options.model_points / 2));
  // Each level's points are where foveation puts them.
  int checked = 0;
  for (std::size_t i = 0; i < p.levels.size(); i += 97) {
    const Eigen::Vector3f q(p.points_mm[3 * i] / 1000.0f, p.points_mm[3 * i + 1] / 1000.0f,
                            p.points_mm[3 * i + 2] / 1000.0f);
    const int level = LevelOf(geometry, q);
    if (level >= 0) {
      ++checked;  // (rounding to millimetres may cross a face)
      EXPECT_EQ(level, p.levels[i]) << i;
    }
  }

  EXPECT_GT(checked, 10);

  std::string error;
  const std::vector<std::uint8_t> bytes = EncodePreview(p, 123456, options, &error);
  ASSERT_FALSE(bytes.empty()) << error;
  EXPECT_LE(bytes.size(), 60000u);
  const std::optional<DecodedPreview> d = DecodePreview(bytes.data(), bytes.size(), &error);
  ASSERT_TRUE(d) << error;
  EXPECT_EQ(d->utime, 123456);
  EXPECT_EQ(d->seq, 42);
  EXPECT_EQ(d->width, 320);
  EXPECT_EQ(d->image_format, "jpeg");
  ASSERT_GT(d->image.size(), 2u);
  EXPECT_EQ(d->image[0], 0xff);  // a JPEG's start-of-image marker
  EXPECT_EQ(d->image[1], 0xd8);
  ASSERT_EQ(d->num_points, static_cast<int>(p.levels.size() + p.instance_of_point.size()));
  // The block: the cloud's points then the instance's, tagged, at the same millimetres.
  const auto x_of = [&](std::size_t i) {
    return static_cast<std::int16_t>(d->points[6 * i] | d->points[6 * i + 1] << 8);
  };
  const std::size_t tags = 6 * static_cast<std::size_t>(d->num_points);
  EXPECT_EQ(x_of(0), p.points_mm[0]);
  EXPECT_EQ(d->points[tags], p.levels[0]);
  EXPECT_EQ(x_of(p.levels.size()), p.instance_points_mm[0]);
  EXPECT_EQ(d->points[tags + p.levels.size()], 128);  // instance 0
  ASSERT_EQ(d->instance_centroids.size(), 1u);
  EXPECT_FLOAT_EQ(d->instance_centroids[0][0], 0.145f);
  EXPECT_EQ(d->level_min.size(), geometry.levels.size());
  EXPECT_TRUE(d->has_truth);
  EXPECT_FLOAT_EQ(d->truth_centroid[2], 1.44f);
  EXPECT_DOUBLE_EQ(d->fovea[2], 1.5f);
}

TEST(Preview, ASmallBudgetLowersTheQualityThenThinsThePoints) {
  const Scene s;
  PreviewOptions options;
  options.max_bytes = 20000;
  FoveaGeometry geometry;
  const Preview p = MakeOne(s, options, &geometry);
  std::string error;
  const std::vector<std::uint8_t> bytes = EncodePreview(p, 1, options, &error);
  ASSERT_FALSE(bytes.empty()) << error;
  EXPECT_LE(bytes.size(), 20000u);
  const auto d = DecodePreview(bytes.data(), bytes.size(), &error);
  ASSERT_TRUE(d) << error;
  EXPECT_LT(d->num_points, static_cast<int>(p.levels.size() + p.instance_of_point.size()));
  // The instance's points are all kept: they are what a viewer is for.
  int instance_points = 0;
  for (int i = 0; i < d->num_points; ++i)
    instance_points += d->points[6 * d->num_points + i] >= 128;
  EXPECT_EQ(instance_points, static_cast<int>(p.instance_of_point.size()));
}

TEST(Preview, AMalformedMessageIsRefusedWithAReason) {
  const Scene s;
  PreviewOptions options;
  FoveaGeometry geometry;
  const Preview p = MakeOne(s, options, &geometry);
  std::string error;
  const std::vector<std::uint8_t> bytes = EncodePreview(p, 1, options, &error);
  ASSERT_FALSE(bytes.empty());
  // Every truncation.
  for (std::size_t n = 0; n < bytes.size(); n += 1 + n / 50) {
    std::string why;
    EXPECT_FALSE(DecodePreview(bytes.data(), n, &why)) << n;
    EXPECT_EQ(why.rfind("preview_t: ", 0), 0u) << why;
  }
  // The counts lie: the image's size (after hash, utime, seq, 2 x int16, 4 floats, colour and
  // "jpeg"), beyond the message; and num_points, over the limit and short of the block.
  const std::size_t image_size_at = 8 + 8 + 8 + 2 + 2 + 16 + 1 + 4 + 5;
  std::vector<std::uint8_t> lie = bytes;
  lie[image_size_at] = 0x7f;
  EXPECT_FALSE(DecodePreview(lie.data(), lie.size(), &error));
  EXPECT_NE(error.find("image_size"), std::string::npos) << error;
  const std::int32_t image_size = (bytes[image_size_at] << 24) | (bytes[image_size_at + 1] << 16) |
                                  (bytes[image_size_at + 2] << 8) | bytes[image_size_at + 3];
  const std::size_t num_points_at = image_size_at + 4 + static_cast<std::size_t>(image_size);
  for (const std::int32_t n : {20001, -1, 5}) {
    lie = bytes;
    for (int b = 0; b < 4; ++b)
      lie[num_points_at + b] =
          static_cast<std::uint8_t>(static_cast<std::uint32_t>(n) >> (24 - 8 * b));
    EXPECT_FALSE(DecodePreview(lie.data(), lie.size(), &error)) << n;
    EXPECT_NE(error.find(n == 5 ? "inflate" : "num_points"), std::string::npos) << error;
  }
  // Another type's bytes of the same length.
  lie = bytes;
  lie[0] ^= 0xff;
  EXPECT_FALSE(DecodePreview(lie.data(), lie.size(), &error));
}

}  // namespace
}  // namespace saccade
