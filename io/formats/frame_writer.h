// Writes a sequence of frames to a folder that pcd: and depth: sources read back, with the
// ground truth beside them (truth.csv) when the frames carry it.
#pragma once

#include "core/frame.h"

#include <cstdint>
#include <fstream>
#include <memory>
#include <string>

namespace saccade {

class FrameWriter {
 public:
  enum class Format { kPcd, kDepth };
  /// Creates `dir` when missing. nullptr with `error` when it cannot be written.
  static std::unique_ptr<FrameWriter> Open(const std::string& dir, Format format,
                                           std::string* error);
  /// Writes frame number `count()` (frame_NNNNNN.pcd, or depth_NNNNNN.png plus rgb_NNNNNN.png
  /// when the cloud has colour, and intrinsics.yaml). False with `error` naming the file.
  bool Write(const Frame& frame, std::string* error);
  std::size_t count() const { return count_; }

 private:
  FrameWriter() = default;
  std::string dir_;
  Format format_ = Format::kPcd;
  std::size_t count_ = 0;
  std::ofstream truth_;
  bool truth_started_ = false;
  std::uintmax_t truth_bytes_ = 0;  // of whole rows (and the header): what a failure cuts back to
};

}  // namespace saccade
