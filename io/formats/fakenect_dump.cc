#include "io/formats/fakenect_dump.h"

#include "core/fail.h"
#include "io/base/text.h"

#include <libfreenect.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

namespace saccade {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kDepthBytes = kKinectWidth * kKinectHeight * sizeof(std::uint16_t);
constexpr std::size_t kColourBytes = kKinectWidth * kKinectHeight * 3;

// The header fakenect expects of a file of `type` ('d' or 'r'), and the pixel bytes after it.
const char* HeaderOf(char type) { return type == 'd' ? "P5 640 480 65535\n" : "P6 640 480 255\n"; }
std::size_t BytesOf(char type) { return type == 'd' ? kDepthBytes : kColourBytes; }

}  // namespace

bool CheckFakenectDump(const std::string& dir, int* depth_frames, std::string* error) {
  const std::string index_path = (fs::path(dir) / "INDEX.txt").string();
  std::ifstream index(index_path);
  if (!IsDirectory(dir)) return Fail(error, dir + ": no such folder (a fakenect dump)");
  if (!index) return Fail(error, index_path + ": cannot open: not a fakenect dump");
  *depth_frames = 0;
  int colour_frames = 0;
  std::string line;
  for (int number = 1; std::getline(index, line); ++number) {
    const std::string where = index_path + ":" + std::to_string(number) + ": ";
    // fakenect stops at an empty line, and reads names as TYPE-SECONDS-TIMESTAMP...
    double seconds = 0;
    unsigned timestamp = 0;
    char type = 0;
    if (line.empty() || std::sscanf(line.c_str(), "%c-%lf-%u", &type, &seconds, &timestamp) != 3 ||
        (type != 'd' && type != 'r' && type != 'a') || line.find('/') != std::string::npos)
      return Fail(error,
                  where + "expected d-, r- or a-SECONDS-TIMESTAMP.EXT, found '" + line + "'");
    const fs::path file = fs::path(dir) / line;
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    if (ec || !IsRegularFile(file.string()))
      return Fail(error, file.string() + ": listed in INDEX.txt but cannot be read");
    if (type == 'a') {  // fakenect reads it whole; an empty one ends its replay there
      if (size != sizeof(freenect_raw_tilt_state))
        return Fail(error, file.string() + ": not a fakenect accelerometer record (" +
                               std::to_string(size) + " bytes, expected " +
                               std::to_string(sizeof(freenect_raw_tilt_state)) + ")");
      continue;
    }
    const std::string header = HeaderOf(type);
    std::ifstream in(file, std::ios::binary);
    std::string first;
    std::getline(in, first);
    if (first + "\n" != header || size != header.size() + BytesOf(type))
      return Fail(error, file.string() + ": not a 640x480 fakenect " +
                             (type == 'd' ? "depth" : "colour") + " frame (expected the header '" +
                             header.substr(0, header.size() - 1) + "' and " +
                             std::to_string(BytesOf(type)) + " bytes after it, " +
                             std::to_string(size) + " in all)");
    (type == 'd' ? *depth_frames : colour_frames) += 1;
  }
  if (*depth_frames == 0) return Fail(error, index_path + ": lists no depth frame");
  return true;
}

std::unique_ptr<FakenectWriter> FakenectWriter::Open(const std::string& dir,
                                                     const ColourCalibration& calibration,
                                                     std::string* error) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  std::unique_ptr<FakenectWriter> w(new FakenectWriter);
  w->dir_ = dir;
  w->calibration_ = calibration;
  std::string why;
  if (ec || !w->index_.Open((fs::path(dir) / "INDEX.txt").string(), &why)) {
    Fail(error, dir + ": cannot create a fakenect dump there: " + (ec ? ec.message() : why));
    return nullptr;
  }
  return w;
}

bool FakenectWriter::Write(const Frame& frame, std::string* error) {
  const Cloud& cloud = *frame.cloud;
  const CameraIntrinsics& k = frame.intrinsics;
  if (static_cast<int>(cloud.width) != k.width || static_cast<int>(cloud.height) != k.height)
    return Fail(error, dir_ + ": frame " + std::to_string(frame.sequence) +
                           " is not an organized image of its intrinsics' size");
  // The frame's depth, then as the colour camera sees it (with the colour of each pixel).
  std::vector<std::uint16_t> depth(cloud.size(), 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const float z = cloud[i].z;
    if (std::isfinite(z) && z > 0 && z < 65.535f)
      depth[i] = static_cast<std::uint16_t>(std::lround(z * 1000.0f));
  }
  const ColourCalibration& c = calibration_;
  std::vector<int> source;
  const auto colour_view =
      RegisterDepth(depth.data(), k, Eigen::Isometry3d::Identity(), c.colour, &source);
  std::vector<std::uint8_t> rgb(kColourBytes, 0);
  for (std::size_t t = 0; t < source.size() && 3 * t < rgb.size(); ++t) {
    if (source[t] < 0) continue;
    const PointT& p = cloud[static_cast<std::size_t>(source[t])];
    rgb[3 * t] = p.r, rgb[3 * t + 1] = p.g, rgb[3 * t + 2] = p.b;
  }
  // What the depth camera sees, as the Kinect's raw disparity.
  const auto ir_view =
      RegisterDepth(colour_view.data(), c.colour, c.colour_from_depth.inverse(), c.depth);
  std::vector<std::uint16_t> raw(ir_view.size());
  for (std::size_t i = 0; i < raw.size(); ++i) raw[i] = MmToKinectDisparity(ir_view[i]);

  const std::int64_t utime = frame.capture_utime;
  // File names are the times: a frame at or before the last one would overwrite or reorder.
  if (last_utime_ && utime <= *last_utime_)
    return Fail(error, dir_ + ": frame " + std::to_string(frame.sequence) + " is captured at " +
                           std::to_string(utime) + " us, not after the frame before it (" +
                           std::to_string(*last_utime_) + " us); a dump's times must increase");
  const double seconds = 1000.0 + utime * 1e-6;  // any epoch: replay follows the differences
  const auto ticks = static_cast<std::uint32_t>(
      static_cast<std::uint64_t>(std::llround(utime * (kKinectClockHz / 1e6))) & 0xffffffffu);
  const auto write = [&](char type, const void* data, std::size_t bytes) {
    char name[96];
    std::snprintf(name, sizeof(name), "%c-%f-%u.%s", type, seconds, ticks,
                  type == 'd' ? "pgm" : "ppm");
    const fs::path path = fs::path(dir_) / name;
    // The file whole, then its line in INDEX.txt: a frame that did not fit is not listed.
    if (!WriteBytes(path.string(),
                    HeaderOf(type) + std::string(static_cast<const char*>(data), bytes), error))
      return false;
    if (index_.Append(std::string(name) + "\n", error)) return true;
    fs::remove(path);
    return false;
  };
  if (c.colour.width != kKinectWidth || c.colour.height != kKinectHeight ||
      c.depth.width != kKinectWidth || c.depth.height != kKinectHeight)
    return Fail(error, dir_ + ": a fakenect dump is 640x480");
  if (!write('d', raw.data(), kDepthBytes) || !write('r', rgb.data(), kColourBytes)) return false;
  last_utime_ = utime;
  return true;
}

}  // namespace saccade
