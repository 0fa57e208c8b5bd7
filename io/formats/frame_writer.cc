#include "io/formats/frame_writer.h"

#include "core/fail.h"
#include "io/base/text.h"
#include "io/formats/cloud_io.h"
#include "io/formats/images.h"
#include "io/formats/truth_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

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

// A frame is written whole or not at all: when a part fails (a full disk), the files already
// written for it are removed and the truth file is cut back to its last whole row, so that
// what is left plays back as a recording.
bool FrameWriter::Write(const Frame& frame, std::string* error) {
  const Cloud& cloud = *frame.cloud;
  const fs::path dir(dir_);
  std::vector<std::string> written;
  auto undo = [&] {
    for (const auto& path : written) std::remove(path.c_str());
    if (truth_started_) {
      truth_.close();
      std::error_code ec;
      if (truth_bytes_ > 0) {
        fs::resize_file(dir / kTruthFileName, truth_bytes_, ec);
        truth_.open(dir / kTruthFileName, std::ios::app);
      } else {
        fs::remove(dir / kTruthFileName, ec);
        truth_started_ = false;
      }
    }
    return false;
  };
  if (format_ == Format::kPcd) {
    const std::string path = (dir / Numbered("frame", count_, "pcd")).string();
    if (!SaveCloud(path, cloud, error)) return false;
    written.push_back(path);
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
    const std::string depth_path = (dir / Numbered("depth", count_, "png")).string();
    if (!WriteDepthPng(depth_path, depth, error)) return false;
    written.push_back(depth_path);
    const std::string rgb_path = (dir / Numbered("rgb", count_, "png")).string();
    if (coloured && !WriteRgbPng(rgb_path, rgb, error)) return undo();
    if (coloured) written.push_back(rgb_path);
  }
  if (frame.truth) {
    if (!truth_started_) {
      truth_.open(dir / kTruthFileName);
      truth_ << TruthCsvHeader() << "\n";
      truth_started_ = true;
    }
    errno = 0;
    truth_ << TruthCsvRow({frame.sequence, frame.capture_utime, *frame.truth}) << "\n";
    truth_.flush();
    if (!truth_) {
      const int why = errno;
      undo();
      return Fail(error, (dir / kTruthFileName).string() + ": cannot write (" +
                             (why != 0 ? std::strerror(why) : "write failed") + ")");
    }
    std::error_code ec;
    truth_bytes_ = fs::file_size(dir / kTruthFileName, ec);
  }
  ++count_;
  return true;
}

}  // namespace saccade
