// Radius neighbourhoods on organized clouds: wide windows sampled, and normals computed only
// where supports read them, once for several descriptions.
#include "core/neighbor_search.h"

#include "core/shot.h"
#include "support/shapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace saccade {
namespace {

using testing::BoxCorner;
using testing::Grid;

// A wavy surface about 0.8 m away, one point per pixel of a 96 x 96 image.
const CameraIntrinsics kWavyIntrinsics{525, 525, 48, 48, 96, 96};
Cloud WavySurface() {
  Cloud surface(96, 96);
  for (int v = 0; v < 96; ++v)
    for (int u = 0; u < 96; ++u) {
      const float z = 0.8f + 0.02f * std::sin(u * 0.15f) * std::cos(v * 0.1f);
      PointT& p = surface.at(u, v);
      p.x = (u - 48) * z / 525, p.y = (v - 48) * z / 525, p.z = z;
    }
  return surface;
}

TEST(OrganizedSearch, WideWindowsAreSampledNotCut) {
  // A fronto-parallel plane one metre away, one point per pixel.
  const CameraIntrinsics k{525, 525, 32, 32, 64, 64};
  Cloud plane(64, 64);
  for (int v = 0; v < 64; ++v)
    for (int u = 0; u < 64; ++u) {
      PointT& p = plane.at(u, v);
      p.x = (u - 32) / 525.0f, p.y = (v - 32) / 525.0f, p.z = 1;
    }
  const std::vector<std::uint8_t> mask(plane.size(), 1);
  const int query = 32 * 64 + 32;
  const float radius = 0.04f;  // 21 pixels
  std::vector<int> all, sampled;
  std::vector<float> d_all, d_sampled;
  MakeOrganizedSearch(plane, k, mask)->Radius(query, radius, &all, &d_all);
  MakeOrganizedSearch(plane, k, mask, 8)->Radius(query, radius, &sampled, &d_sampled);
  // Every pixel of the disc, or every third one (21 px / 8 rounds up to a step of 3).
  EXPECT_NEAR(double(all.size()), EIGEN_PI * 21 * 21, 60);
  EXPECT_NEAR(double(sampled.size()), double(all.size()) / 9, 15);
  // The samples lie on one image-wide grid, so a neighbouring query reads the same pixels.
  for (int i : sampled) {
    EXPECT_EQ(i % 64 % 3, 0);
    EXPECT_EQ(i / 64 % 3, 0);
  }
  std::vector<int> beside;
  MakeOrganizedSearch(plane, k, mask, 8)->Radius(query + 1, radius, &beside, &d_sampled);
  std::vector<int> common;
  std::sort(sampled.begin(), sampled.end());
  std::sort(beside.begin(), beside.end());
  std::set_intersection(sampled.begin(), sampled.end(), beside.begin(), beside.end(),
                        std::back_inserter(common));
  EXPECT_GT(common.size(), sampled.size() * 9 / 10);
  MakeOrganizedSearch(plane, k, mask, 8)->Radius(query, radius, &sampled, &d_sampled);
  // The sample spans the whole support, not just its middle.
  const float widest = *std::max_element(d_sampled.begin(), d_sampled.end());
  EXPECT_GT(widest, 0.8f * radius * radius);
  EXPECT_LE(widest, radius * radius);
  for (int i : sampled) EXPECT_NE(std::find(all.begin(), all.end(), i), all.end());
}

TEST(OrganizedSearch, NormalsOnlyWhereSupportsReadThemGiveTheSameDescriptors) {
  // A wavy surface about 0.8 m away, one point per pixel; wide supports sampled to 6 px.
  const CameraIntrinsics k = kWavyIntrinsics;
  const Cloud surface = WavySurface();
  const std::vector<std::uint8_t> everywhere(surface.size(), 1);
  const auto search = MakeOrganizedSearch(surface, k, everywhere, 6);
  std::vector<int> keypoints;
  for (int v = 30; v <= 66; v += 6)
    for (int u = 30; u <= 66; u += 6) keypoints.push_back(v * 96 + u);
  DescribeOptions options;
  options.shot_radius_m = 0.04f;  // about 26 px: sampled every 5th pixel
  options.lrf_radius_m = 0.03f;
  const Supports supports = FindSupports(surface, keypoints, *search, options);
  const std::vector<std::uint8_t> wanted = SupportMask(supports, surface.size());
  const auto read = std::count(wanted.begin(), wanted.end(), 1);
  EXPECT_GT(read, 0);
  EXPECT_LT(read, static_cast<long>(surface.size()) / 10);  // the sampling grid, not the image
  const Descriptors all = DescribeKeypoints(surface, OrganizedNormals(surface, k, everywhere, 10),
                                            keypoints, supports, options);
  const Descriptors some = DescribeKeypoints(surface, OrganizedNormals(surface, k, wanted, 10),
                                             keypoints, supports, options);
  ASSERT_EQ(all.size(), keypoints.size());
  EXPECT_EQ(all.keypoint, some.keypoint);
  EXPECT_EQ(all.shot, some.shot);
}

TEST(SceneNormals, NormalsAskedForInPartsAreThoseOfOneCall) {
  const Cloud surface = WavySurface();
  const CameraIntrinsics& k = kWavyIntrinsics;
  std::vector<std::uint8_t> left(surface.size(), 0), right(surface.size(), 0),
      both(surface.size(), 0);
  for (std::size_t i = 0; i < surface.size(); ++i) {
    const int u = int(i % 96);
    left[i] = u < 60;
    right[i] = u >= 40;
    both[i] = left[i] || right[i];
  }
  const Normals whole = OrganizedNormals(surface, k, both, 10);
  SceneNormals shared;
  const Normals& first = shared.On(surface, &k, 10, left, SerialFor);
  EXPECT_TRUE(first[10].allFinite());
  EXPECT_FALSE(first[95].allFinite());  // not asked for yet
  const Normals& after = shared.On(surface, &k, 10, right, SerialFor);
  for (std::size_t i = 0; i < surface.size(); ++i) ASSERT_EQ(after[i], whole[i]) << i;
  // Another k starts afresh: only what it asked for is set.
  const Normals& other = shared.On(surface, &k, 20, right, SerialFor);
  EXPECT_FALSE(other[10].allFinite());
  EXPECT_TRUE(other[95].allFinite());
}

}  // namespace
}  // namespace saccade
