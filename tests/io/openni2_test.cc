// OpenNI2 through the real libOpenNI2 with no sensor: the project's virtual device serves
// synthetic depth images as a live camera; openni::Recorder writes an .oni, and Debian's .oni
// driver plays it back. Every frame is checked against the image it came from.
#include "io/formats/frame_writer.h"
#include "io/formats/images.h"
#include "io/sources/frame_source.h"
#include "io/sources/openni2_source.h"
#include "support/depth_folder.h"
#include "support/processes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <unistd.h>

namespace saccade {
namespace {

namespace fs = std::filesystem;
constexpr int kImages = 5;

class OpenNI2Test : public ::testing::Test {
 protected:
  // The images are written once, and the folder named before libOpenNI2 starts (the driver
  // looks for it when libOpenNI2 initializes).
  static void SetUpTestSuite() {
    // One folder per process: ctest runs the tests of this file in parallel processes.
    dir_ = ::testing::TempDir() + "saccade_virtual_device_" + std::to_string(getpid());
    testing::WriteSyntheticDepthFolder(dir_, kImages);
    std::string error;
    for (int i = 0; i < kImages; ++i) {
      DepthImage image;
      char name[64];
      std::snprintf(name, sizeof(name), "/depth_%06d.png", i);
      ASSERT_TRUE(ReadDepthImage(dir_ + name, &image, &error)) << error;
      images_.push_back(image);
    }
    setenv("SACCADE_VIRTUAL_DEVICE", dir_.c_str(), 1);
  }

  // The image a frame shows, found by content; -1 when it matches none. The .oni round trip
  // goes through Debian's 16z codec, which was seen to alter the last 8 pixels of a frame by
  // 1 mm, so all but kTail pixels must agree exactly.
  static int ImageOf(const Frame& frame) {
    constexpr int kTail = 16;
    for (int i = 0; i < kImages; ++i) {
      int differ = 0;
      for (std::size_t p = 0; differ <= kTail && p < images_[i].data.size(); ++p) {
        const float z = (*frame.cloud)[p].z;
        const std::uint16_t mm = images_[i].data[p];
        differ += !(mm == 0 ? !std::isfinite(z) : std::abs(z - mm * 0.001f) < 1e-6f);
      }
      if (differ <= kTail) return i;
    }
    return -1;
  }

  static std::string dir_;
  static std::vector<DepthImage> images_;
};
std::string OpenNI2Test::dir_;
std::vector<DepthImage> OpenNI2Test::images_;

TEST_F(OpenNI2Test, LiveDeviceDeliversTheImagesInOrderWithKinectIntrinsics) {
  std::string error;
  auto source = OpenSource("openni2://", &error);
  ASSERT_TRUE(source) << error;
  EXPECT_TRUE(source->Live());
  Frame f;
  std::int64_t previous_utime = 0;
  for (int n = 0; n < 6; ++n) {
    ASSERT_EQ(source->Next(&f, &error), FrameSource::Status::kFrame) << error;
    EXPECT_NEAR(f.intrinsics.fx, 525.0, 1e-3);
    EXPECT_NEAR(f.intrinsics.cx, 319.5, 1e-9);
    const int image = ImageOf(f);
    ASSERT_GE(image, 0) << "frame " << f.sequence << " matches no source image";
    // The device's timestamp says which image it is: frame k (from 1) at k / 30 s.
    const long k = std::lround(f.capture_utime * 30 / 1e6);
    EXPECT_EQ(image, (k - 1) % kImages);
    EXPECT_GT(f.capture_utime, previous_utime) << "a frame repeated or out of order";
    previous_utime = f.capture_utime;
  }
  EXPECT_EQ(source->Stats().state, "streaming");
}

TEST_F(OpenNI2Test, DevicesAreChosenByIndexOrSerialAndUnknownOnesAreErrors) {
  std::string error;
  EXPECT_TRUE(OpenSource("openni2://#0", &error)) << error;
  EXPECT_TRUE(OpenSource("openni2://SACCADE-VIRTUAL-0", &error)) << error;
  EXPECT_FALSE(OpenSource("openni2://#3", &error));
  EXPECT_NE(error.find("1 found"), std::string::npos) << error;
  EXPECT_FALSE(OpenSource("openni2://NO-SUCH-SERIAL", &error));
  EXPECT_NE(error.find("saccade-virtual://"), std::string::npos) << error;
}

TEST_F(OpenNI2Test, RecordedOniPlaysBackFrameByFrame) {
  const std::string oni = dir_ + ".oni";
  std::string error;
  int recorded = 0;
  {
    auto device = OpenOpenNI2Device("", ColourOptions{}, 0, &error);
    ASSERT_TRUE(device) << error;
    ASSERT_TRUE(device->StartRecording(oni, &error)) << error;
    Frame f;
    for (; recorded < 8; ++recorded)
      ASSERT_EQ(device->Next(&f, &error), FrameSource::Status::kFrame) << error;
    device->StopRecording();
  }
  auto playback = OpenSource(oni + "?mode=step", &error);
  ASSERT_TRUE(playback) << error;
  EXPECT_FALSE(playback->Live());
  Frame f;
  int played = 0;
  int previous = -1;
  while (playback->Next(&f, &error) == FrameSource::Status::kFrame) {
    const int image = ImageOf(f);
    ASSERT_GE(image, 0) << "played frame " << played << " matches no source image";
    if (previous >= 0) {
      EXPECT_EQ(image, (previous + 1) % kImages) << "frames out of order";
    }
    previous = image;
    EXPECT_EQ(f.sequence, static_cast<std::uint64_t>(played));
    ++played;
  }
  // The recorder keeps what the camera delivered while it ran: at least what we read.
  EXPECT_GE(played, recorded);
  EXPECT_EQ(playback->Next(&f, &error), FrameSource::Status::kEnd);
}

TEST_F(OpenNI2Test, ASilentDeviceIsReopenedAndFramesResume) {
  setenv("SACCADE_VIRTUAL_DEVICE_STALL_AFTER", "3", 1);
  std::string error;
  auto source = OpenSource("openni2://", &error);
  unsetenv("SACCADE_VIRTUAL_DEVICE_STALL_AFTER");  // the reopened device streams on
  ASSERT_TRUE(source) << error;
  Frame f;
  // At most three frames come before the stall; the sixth needs a reopened device.
  for (int n = 0; n < 6; ++n) {
    ASSERT_EQ(source->Next(&f, &error), FrameSource::Status::kFrame) << error;
    ASSERT_GE(ImageOf(f), 0);
  }
  EXPECT_EQ(source->Stats().reconnects, 1u);
  EXPECT_EQ(source->Stats().state, "streaming");
}

// A camera that goes and comes back many times (a loose cable): every time it falls silent
// it is reopened, and frames resume each time, in order of the device's images.
TEST_F(OpenNI2Test, ADeviceThatGoesSilentFiveTimesIsReopenedEachTime) {
  // Every opened stream, not only the first; unset however the test ends.
  setenv("SACCADE_VIRTUAL_DEVICE_STALL_AFTER", "3", 1);
  struct Unset {
    ~Unset() { unsetenv("SACCADE_VIRTUAL_DEVICE_STALL_AFTER"); }
  } unset;
  std::string error;
  auto source = OpenSource("openni2://", &error);
  ASSERT_TRUE(source) << error;
  Frame f;
  int frames = 0;
  while (source->Stats().reconnects < 5 && frames < 40) {
    ASSERT_EQ(source->Next(&f, &error), FrameSource::Status::kFrame) << error;
    ASSERT_GE(ImageOf(f), 0);
    ++frames;
  }
  // A loaded machine may see a reopened stream silent for 2 s before its first frame: one more.
  EXPECT_GE(source->Stats().reconnects, 5u);
  // At most three frames a connection: the connections gave every frame read.
  EXPECT_LE(frames, 3 * static_cast<int>(source->Stats().reconnects + 1));
  EXPECT_GE(frames, 5);
  ASSERT_EQ(source->Next(&f, &error), FrameSource::Status::kFrame) << error;
  EXPECT_EQ(source->Stats().state, "streaming");
}

// A camera unplugged and plugged back 100 times in one run (its folder taken away and put
// back): each time its stream falls silent, the reopen fails while it is away (the state says
// why), and once it is back the device is reopened and frames resume, each a whole image of the
// device. A cycle takes about 2.6 s: the 2 s of silence that mean a camera is gone, then the
// first 0.5 s step of the back-off.
TEST_F(OpenNI2Test, ACameraThatGoesAndComesBackAHundredTimesIsReopenedEachTime) {
  setenv("SACCADE_VIRTUAL_DEVICE_STALL_AFTER", "2", 1);
  const std::string away = dir_ + ".away";
  struct Restore {
    std::string dir, away;
    ~Restore() {
      unsetenv("SACCADE_VIRTUAL_DEVICE_STALL_AFTER");
      if (fs::exists(away)) fs::rename(away, dir);
    }
  } restore{dir_, away};
  std::string error;
  auto source = OpenSource("openni2://", &error);
  ASSERT_TRUE(source) << error;
  Frame f;
  int failed_reopens = 0;
  constexpr unsigned kCycles = 100;
  for (unsigned cycle = 0; cycle < kCycles; ++cycle) {
    // Connected (again): a frame of the device.
    ASSERT_TRUE(testing::WaitFor([&] {
      const SourceStats s = source->Stats();
      return s.reconnects == cycle && s.state == "streaming";
    })) << "cycle "
        << cycle << ": " << source->Stats().state;
    ASSERT_EQ(source->Next(&f, &error), FrameSource::Status::kFrame) << error;
    ASSERT_GE(ImageOf(f), 0) << "cycle " << cycle;
    // Unplugged: silent, and the reopen fails while the device is away.
    fs::rename(dir_, away);
    ASSERT_TRUE(testing::WaitFor([&] {
      const std::string state = source->Stats().state;
      return state.rfind("reconnecting: ", 0) == 0 && state != "reconnecting: no frame for 2 s";
    })) << "cycle "
        << cycle << ": " << source->Stats().state;
    ++failed_reopens;
    fs::rename(away, dir_);  // plugged back
  }
  ASSERT_TRUE(testing::WaitFor([&] { return source->Stats().reconnects == kCycles; }));
  ASSERT_EQ(source->Next(&f, &error), FrameSource::Status::kFrame) << error;
  EXPECT_GE(ImageOf(f), 0);
  EXPECT_EQ(failed_reopens, 100);
  EXPECT_EQ(source->Stats().state, "streaming");
}

}  // namespace
}  // namespace saccade
