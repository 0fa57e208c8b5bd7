// Depth and colour images and the intrinsics file: round trips and one-line errors.
#include "io/formats/images.h"

#include <gtest/gtest.h>

#include <png.h>
#include <zlib.h>

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

// A PNG of `width` x `height` pixels in `format` (libpng's simplified API), its bytes.
std::string PngBytes(const std::string& path, std::uint32_t format, int width, int height) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = width, png.height = height, png.format = format;
  std::vector<std::uint8_t> pixels(PNG_IMAGE_SIZE(png), 7);
  EXPECT_TRUE(png_image_write_to_file(&png, path.c_str(), 0, pixels.data(), 0, nullptr));
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(Images, DepthMustBeSixteenBitGreyAndHeadersMustNotClaimGigapixels) {
  const std::string dir = ::testing::TempDir();
  DepthImage depth;
  std::string error;
  const std::string grey8 = dir + "saccade_grey8_depth.png";
  PngBytes(grey8, PNG_FORMAT_GRAY, 4, 3);
  EXPECT_FALSE(ReadDepthImage(grey8, &depth, &error));
  EXPECT_EQ(error,
            grey8 + ": a depth image must be 16-bit grey (millimetres); this one is 8-bit grey");
  const std::string rgb16 = dir + "saccade_rgb16_depth.png";
  PngBytes(rgb16, PNG_FORMAT_LINEAR_RGB, 4, 3);
  EXPECT_FALSE(ReadDepthImage(rgb16, &depth, &error));
  EXPECT_NE(error.find("this one is 16-bit colour"), std::string::npos) << error;
  // A 1x1 PNG whose header says 100000 x 100000 (its CRC mended): refused before allocating.
  const std::string huge = dir + "saccade_huge_depth.png";
  std::string bytes = PngBytes(huge, PNG_FORMAT_LINEAR_Y, 1, 1);
  const std::size_t ihdr = bytes.find("IHDR");
  ASSERT_NE(ihdr, std::string::npos);
  for (int k = 0; k < 2; ++k)  // width, then height, big-endian
    for (int b = 0; b < 4; ++b)
      bytes[ihdr + 4 + 4 * k + b] = static_cast<char>((100000u >> (24 - 8 * b)) & 0xff);
  const uLong crc = crc32(0, reinterpret_cast<const Bytef*>(bytes.data() + ihdr), 17);
  for (int b = 0; b < 4; ++b)
    bytes[ihdr + 17 + b] = static_cast<char>((crc >> (24 - 8 * b)) & 0xff);
  std::ofstream(huge, std::ios::binary) << bytes;
  EXPECT_FALSE(ReadDepthImage(huge, &depth, &error));
  EXPECT_NE(error.find("100000x100000 pixels, more than"), std::string::npos) << error;
  EXPECT_FALSE(ReadDepthImage("/dev/zero", &depth, &error));
  EXPECT_EQ(error, "/dev/zero: not a regular file (a device or a pipe?), not an image");
}

}  // namespace
}  // namespace saccade
