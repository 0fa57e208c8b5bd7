// Depth and colour images and the intrinsics file: round trips and one-line errors.
#include "io/images.h"

#include <gtest/gtest.h>

#include <fstream>
#include <random>

namespace saccade {
namespace {

std::string Temp(const std::string& name) { return ::testing::TempDir() + name; }

TEST(Images, DepthPngRoundTripsEverySixteenBitValue) {
  DepthImage d;
  d.width = 64, d.height = 48;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> value(0, 65535);
  for (int i = 0; i < d.width * d.height; ++i)
    d.data.push_back(static_cast<std::uint16_t>(value(rng)));
  d.data[0] = 0, d.data[1] = 65535, d.data[2] = 1;
  std::string error;
  ASSERT_TRUE(WriteDepthPng(Temp("d.png"), d, &error)) << error;
  DepthImage back;
  ASSERT_TRUE(ReadDepthImage(Temp("d.png"), &back, &error)) << error;
  EXPECT_EQ(back.width, 64);
  EXPECT_EQ(back.height, 48);
  EXPECT_EQ(back.data, d.data);
}

TEST(Images, RgbPngRoundTrips) {
  RgbImage c;
  c.width = 5, c.height = 3, c.channels = 3;
  for (int i = 0; i < 45; ++i) c.data.push_back(static_cast<std::uint8_t>(i * 5));
  std::string error;
  ASSERT_TRUE(WriteRgbPng(Temp("c.png"), c, &error)) << error;
  RgbImage back;
  ASSERT_TRUE(ReadRgbImage(Temp("c.png"), &back, &error)) << error;
  EXPECT_EQ(back.data, c.data);
}

TEST(Images, CorruptOrMissingImageNamesTheFile) {
  std::ofstream(Temp("bad.png")) << "not a png";
  DepthImage d;
  std::string error;
  EXPECT_FALSE(ReadDepthImage(Temp("bad.png"), &d, &error));
  EXPECT_NE(error.find("bad.png"), std::string::npos) << error;
  EXPECT_FALSE(ReadDepthImage(Temp("missing.tiff"), &d, &error));
  EXPECT_NE(error.find("missing.tiff"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
}

TEST(Images, IntrinsicsRoundTripAndStrictKeys) {
  const IntrinsicsFile k{525.5, 524.25, 319.5, 239.75, 640, 480};
  std::string error;
  ASSERT_TRUE(WriteIntrinsicsFile(Temp("k.yaml"), k, &error)) << error;
  IntrinsicsFile back;
  ASSERT_TRUE(ReadIntrinsicsFile(Temp("k.yaml"), &back, &error)) << error;
  EXPECT_EQ(back.fx, k.fx);
  EXPECT_EQ(back.fy, k.fy);
  EXPECT_EQ(back.cx, k.cx);
  EXPECT_EQ(back.cy, k.cy);
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.height, 480);

  std::ofstream(Temp("k2.yaml")) << "fx: 525\nfy: 525\ncx: 1\ncy: 1\nwidth: 2\nheight: 2\nfz: 3\n";
  EXPECT_FALSE(ReadIntrinsicsFile(Temp("k2.yaml"), &back, &error));
  EXPECT_NE(error.find("line 7: unknown key 'fz'"), std::string::npos) << error;
  std::ofstream(Temp("k3.yaml")) << "fx: 525\n";
  EXPECT_FALSE(ReadIntrinsicsFile(Temp("k3.yaml"), &back, &error));
  EXPECT_NE(error.find("missing key 'fy'"), std::string::npos) << error;
}

}  // namespace
}  // namespace saccade
