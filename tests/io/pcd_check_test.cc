// The PCD check in front of PCL's reader: every real PCD of ../shared/data passes, and each
// bad file of a corpus (not PCD at all, lying headers, truncated or corrupt data, types
// Saccade cannot represent) is refused with one line naming the file, before PCL sees it.
#include "io/formats/pcd_check.h"
#include "io/formats/cloud_io.h"
#include "support/test_data.h"

#include <gtest/gtest.h>

#include <pcl/io/lzf.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include <sys/stat.h>
#include <unistd.h>

namespace saccade {
namespace {

namespace fs = std::filesystem;

const char kHeader[] =
    "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\n"
    "TYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\n";

std::string Binary(const std::string& header_tail, std::size_t points) {
  std::string s = std::string(kHeader) + header_tail;
  for (std::size_t i = 0; i < points; ++i) {
    const float v[3] = {0.1f * i, 0.2f, 1.0f};
    s.append(reinterpret_cast<const char*>(v), sizeof v);
    s.append("\xff\x80\x40\x00", 4);
  }
  return s;
}

// A binary_compressed body for two points with the given size words.
std::string Compressed(int lie_compressed, int lie_uncompressed, bool corrupt) {
  std::string raw = Binary("", 2).substr(std::strlen(kHeader));
  std::vector<char> packed(raw.size() * 2 + 16);
  unsigned n = pcl::lzfCompress(raw.data(), static_cast<unsigned>(raw.size()), packed.data(),
                                static_cast<unsigned>(packed.size()));
  if (n == 0) {  // too small to compress: store literally (LZF's literal run)
    packed[0] = static_cast<char>(raw.size() - 1);
    std::memcpy(packed.data() + 1, raw.data(), raw.size());
    n = static_cast<unsigned>(raw.size() + 1);
  }
  if (corrupt) packed[0] = static_cast<char>(0xff);
  const std::uint32_t words[2] = {
      n + static_cast<std::uint32_t>(lie_compressed),
      static_cast<std::uint32_t>(raw.size()) + static_cast<std::uint32_t>(lie_uncompressed)};
  std::string s = std::string(kHeader) + "DATA binary_compressed\n";
  s.append(reinterpret_cast<const char*>(words), sizeof words);
  s.append(packed.data(), n);
  return s;
}

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  s.replace(s.find(from), from.size(), to);
  return s;
}

struct BadPcd {
  const char* name;
  std::string bytes;
  const char* why;  // a piece of the one-line error
};

std::vector<BadPcd> Corpus() {
  const std::string good_binary = Binary("DATA binary\n", 2);
  const std::string good_ascii =
      std::string(kHeader) + "DATA ascii\n0 0.2 1 4286595072\n0.1 0.2 1 4286595072\n";
  return {
      {"empty", "", "empty file"},
      {"png", "\x89PNG\r\n\x1a\n\0\0\0\rIHDR", "binary bytes in its header"},
      {"text", "hello world\n", "not a PCD file (it starts with 'hello')"},
      {"bom", "\xef\xbb\xbf# .PCD v0.7\nVERSION 0.7\n", "binary bytes in its header"},
      {"random", std::string("\x13\x37\x00\xfe\x01\x02\x03", 7), "binary bytes in its header"},
      {"no-data-line", Replace(good_ascii, "DATA ascii\n", ""), "no DATA line"},
      {"unknown-data", Replace(good_ascii, "DATA ascii", "DATA zip"), "DATA must be"},
      {"unknown-keyword", Replace(good_ascii, "VIEWPOINT", "VIEWPONT"), "unknown header keyword"},
      {"viewpoint-nan", Replace(good_ascii, "VIEWPOINT 0 0 0", "VIEWPOINT nan 0 0"),
       "VIEWPOINT must be"},
      {"viewpoint-short", Replace(good_ascii, "VIEWPOINT 0 0 0 1 0 0 0", "VIEWPOINT 0 0 0 1"),
       "VIEWPOINT must be"},
      {"viewpoint-not-a-rotation", Replace(good_ascii, "0 0 0 1 0 0 0", "0 0 0 2 0 0 0"),
       "VIEWPOINT must be"},
      {"no-fields", Replace(good_ascii, "FIELDS x y z rgb\n", ""), "no FIELDS line"},
      {"no-width", Replace(good_ascii, "WIDTH 2\n", ""), "no WIDTH line"},
      {"width-zero", Replace(good_ascii, "WIDTH 2", "WIDTH 0"), "WIDTH must be a whole number"},
      {"width-negative", Replace(good_ascii, "WIDTH 2", "WIDTH -2"), "WIDTH must be"},
      {"width-huge", Replace(good_ascii, "WIDTH 2", "WIDTH 4294967297"), "WIDTH must be"},
      {"height-huge",
       Replace(Replace(good_binary, "HEIGHT 1", "HEIGHT 100000000"), "WIDTH 2", "WIDTH 100000"),
       "more than 100000000 points"},
      {"points-lie", Replace(good_ascii, "POINTS 2", "POINTS 3"), "is not WIDTH x HEIGHT"},
      {"size-negative", Replace(good_ascii, "SIZE 4 4 4 4", "SIZE 4 4 -4 4"), "SIZE must be"},
      {"size-three", Replace(good_ascii, "SIZE 4 4 4 4", "SIZE 4 4 3 4"), "SIZE must be"},
      {"size-short", Replace(good_ascii, "SIZE 4 4 4 4", "SIZE 4 4 4"), "different numbers"},
      {"type-unknown", Replace(good_ascii, "TYPE F F F U", "TYPE F F Q U"), "TYPE must be"},
      {"count-zero", Replace(good_ascii, "COUNT 1 1 1 1", "COUNT 1 1 0 1"), "COUNT must be"},
      {"count-negative", Replace(good_ascii, "COUNT 1 1 1 1", "COUNT 1 -1 1 1"), "COUNT must be"},
      {"count-three-z", Replace(good_ascii, "COUNT 1 1 1 1", "COUNT 1 1 3 1"),
       "field 'z' is F 4 x3"},
      {"double-xyz", Replace(good_binary, "SIZE 4 4 4 4", "SIZE 8 8 8 4"), "field 'x' is F 8"},
      {"int-xyz", Replace(good_binary, "TYPE F F F U", "TYPE I I I U"), "field 'x' is I 4"},
      {"uint8-xyz",
       Replace(Replace(good_binary, "SIZE 4 4 4 4", "SIZE 1 1 1 4"), "TYPE F F F U",
               "TYPE U U U U"),
       "field 'x' is U 1"},
      {"no-z",
       Replace(Replace(Replace(Replace(good_ascii, "x y z rgb", "x y rgb"), "SIZE 4 4 4 4",
                               "SIZE 4 4 4"),
                       "TYPE F F F U", "TYPE F F U"),
               "COUNT 1 1 1 1", "COUNT 1 1 1"),
       "no x, y and z fields"},
      {"rgb-one-byte", Replace(good_binary, "SIZE 4 4 4 4", "SIZE 4 4 4 1"),
       "'rgb' must be 4 bytes"},
      {"ascii-word", Replace(good_ascii, "0.1 0.2 1", "0.1 zero 1"), "'zero' is not a number"},
      {"ascii-short-line", Replace(good_ascii, "0.1 0.2 1 4286595072", "0.1 0.2 1"),
       "has 3 values"},
      {"ascii-truncated", Replace(good_ascii, "0.1 0.2 1 4286595072\n", ""), "has 1 points"},
      {"binary-truncated", good_binary.substr(0, good_binary.size() - 5), "truncated"},
      {"binary-no-data",
       Replace(good_binary, good_binary.substr(good_binary.find("DATA binary\n") + 12), ""),
       "truncated"},
      {"compressed-no-words", std::string(kHeader) + "DATA binary_compressed\n\x01\x02",
       "no size words"},
      {"compressed-size-lies", Compressed(1000, 0, false), "the file has"},
      {"compressed-unpacked-lies", Compressed(0, 4096, false), "the header needs"},
      {"compressed-corrupt", Compressed(0, 0, true), "is corrupt"},
  };
}

TEST(PcdCheck, EveryBadFileIsRefusedWithOneLineNamingIt) {
  const std::string dir = ::testing::TempDir() + "saccade_bad_pcd_" + std::to_string(getpid());
  fs::create_directories(dir);
  for (const BadPcd& bad : Corpus()) {
    const std::string path = dir + "/" + bad.name + ".pcd";
    std::ofstream(path, std::ios::binary) << bad.bytes;
    std::string error;
    EXPECT_FALSE(LoadCloud(path, &error)) << bad.name;
    EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << bad.name << ": " << error;
    EXPECT_NE(error.find(bad.why), std::string::npos) << bad.name << ": " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << bad.name;
  }
}

TEST(PcdCheck, GoodFilesOfEveryKindPass) {
  const std::string dir = ::testing::TempDir() + "saccade_good_pcd_" + std::to_string(getpid());
  fs::create_directories(dir);
  const std::string ascii =
      std::string(kHeader) + "DATA ascii\n0 0.2 1 4286595072\r\nnan nan nan 0\n";
  for (const auto& [name, bytes] :
       std::vector<std::pair<std::string, std::string>>{{"ascii", ascii},
                                                        {"binary", Binary("DATA binary\n", 2)},
                                                        {"compressed", Compressed(0, 0, false)}}) {
    const std::string path = dir + "/" + name + ".pcd";
    std::ofstream(path, std::ios::binary) << bytes;
    std::string error;
    const auto cloud = LoadCloud(path, &error);
    ASSERT_TRUE(cloud) << name << ": " << error;
    EXPECT_EQ(cloud->size(), 2u) << name;
  }
}

// The VIEWPOINT (the sensor's pose) survives a save and a load: normals are turned towards its
// origin, and it was once dropped on load (a model saved with its capture's viewpoint was then
// not found).
TEST(PcdCheck, TheViewpointSurvivesASaveAndALoad) {
  Cloud cloud;
  PointT p;
  p.x = 0.1f, p.y = 0.2f, p.z = 1.0f;
  cloud.push_back(p);
  cloud.sensor_origin_ = Eigen::Vector4f(0.3f, -0.25f, -0.85f, 0.0f);
  cloud.sensor_orientation_ =
      Eigen::Quaternionf(Eigen::AngleAxisf(0.35f, Eigen::Vector3f::UnitY()));
  const std::string path =
      ::testing::TempDir() + "saccade_viewpoint_" + std::to_string(getpid()) + ".pcd";
  std::string error;
  ASSERT_TRUE(SaveCloud(path, cloud, &error)) << error;
  const auto loaded = LoadCloud(path, &error);
  ASSERT_TRUE(loaded) << error;
  EXPECT_TRUE(loaded->sensor_origin_.head<3>().isApprox(cloud.sensor_origin_.head<3>(), 1e-5f));
  EXPECT_TRUE(loaded->sensor_orientation_.isApprox(cloud.sensor_orientation_, 1e-5f));
  std::remove(path.c_str());
}

TEST(PcdCheck, DevicesPipesAndFoldersAreRefusedWithoutBeingRead) {
  std::string error;
  EXPECT_FALSE(LoadCloud("/dev/zero", &error));
  EXPECT_EQ(error, "/dev/zero: not a regular file (a device or a pipe?), not a PCD file");
  const std::string fifo = ::testing::TempDir() + "saccade_fifo_" + std::to_string(getpid());
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_FALSE(LoadCloud(fifo, &error));  // would block forever if it were opened
  EXPECT_NE(error.find("not a regular file"), std::string::npos) << error;
  unlink(fifo.c_str());
  EXPECT_FALSE(LoadCloud("/tmp", &error));
  EXPECT_EQ(error, "/tmp: is a directory, not a PCD file");
}

TEST(PcdCheck, EveryRealPcdOfTheSharedDataPasses) {
  SACCADE_REQUIRE_DATA("pcl_test/milk.pcd");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(SACCADE_DATA_DIR)) {
    if (entry.path().extension() != ".pcd") continue;
    PcdHeader header;
    std::string error;
    EXPECT_TRUE(CheckPcdFile(entry.path().string(), &header, &error)) << error;
    ++files;
  }
  EXPECT_GT(files, 50);
}

}  // namespace
}  // namespace saccade
