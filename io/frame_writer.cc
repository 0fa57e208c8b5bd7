#include "io/frame_writer.h"

#include "core/fail.h"
#include "io/cloud_io.h"
#include "io/images.h"
#include "io/text.h"
#include "io/truth_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace saccade {

namespace fs = std::filesystem;

namespace {

std::string Numbered(const std::string& prefix, std::size_t i, const char* ext) {
  char name[64];
  std::snprintf(name, sizeof(name), "%s_%06zu.%s", prefix.c_str(), i, ext);
  return name;
}

}  // namespace

std::unique_ptr<FrameWriter> FrameWriter::Open(const std::string& dir, Format format,
                                               std::string* error) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !IsDirectory(dir)) {
    Fail(error, dir + ": cannot create output folder" + (ec ? ": " + ec.message() : ""));
    return nullptr;
  }
  std::unique_ptr<FrameWriter> w(new FrameWriter);
  w->dir_ = dir;
  w->format_ = format;
  return w;
}

bool FrameWriter::Write(const Frame& frame, std::string* error) {
  const Cloud& cloud = *frame.cloud;
  const fs::path dir(dir_);
  if (format_ == Format::kPcd) {
    if (!SaveCloud((dir / Numbered("frame", count_, "pcd")).string(), cloud, error)) return false;
  } else {
    const auto& k = frame.intrinsics;
    if (static_cast<int>(cloud.width) != k.width || static_cast<int>(cloud.height) != k.height) {
      return Fail(error, dir_ + ": frame " + std::to_string(frame.sequence) +
                             " is not an organized image of its intrinsics' size");
    }
    if (count_ == 0) {
      const IntrinsicsFile file{k.fx, k.fy, k.cx, k.cy, k.width, k.height};
      if (!WriteIntrinsicsFile((dir / "intrinsics.yaml").string(), file, error)) return false;
    }
    DepthImage depth;
    depth.width = k.width;
    depth.height = k.height;
    depth.data.assign(cloud.size(), 0);
    RgbImage rgb;
    rgb.width = k.width;
    rgb.height = k.height;
    rgb.channels = 3;
    rgb.data.assign(cloud.size() * 3, 0);
    bool coloured = false;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const PointT& p = cloud[i];
      if (std::isfinite(p.z) && p.z > 0 && p.z < 65.535f)
        depth.data[i] = static_cast<std::uint16_t>(std::lround(p.z * 1000.0f));
      rgb.data[3 * i] = p.r, rgb.data[3 * i + 1] = p.g, rgb.data[3 * i + 2] = p.b;
      coloured = coloured || p.r || p.g || p.b;
    }
    if (!WriteDepthPng((dir / Numbered("depth", count_, "png")).string(), depth, error))
      return false;
    if (coloured && !WriteRgbPng((dir / Numbered("rgb", count_, "png")).string(), rgb, error))
      return false;
  }
  if (frame.truth) {
    if (!truth_started_) {
      truth_.open(dir / kTruthFileName);
      truth_ << TruthCsvHeader() << "\n";
      truth_started_ = true;
    }
    truth_ << TruthCsvRow({frame.sequence, frame.capture_utime, *frame.truth}) << "\n";
    truth_.flush();
    if (!truth_) {
      return Fail(
          error, (dir / kTruthFileName).string() + ": cannot write (" + std::strerror(errno) + ")");
    }
  }
  ++count_;
  return true;
}

}  // namespace saccade
