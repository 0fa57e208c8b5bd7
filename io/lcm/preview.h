// The preview's wire form (saccade.preview_t, io/lcm/lcmtypes/preview_t.lcm): the image as JPEG,
// the points compressed with zlib. Encoded by the daemon's bus, decoded (checked) by viewers.
#pragma once

#include "core/pictures/preview.h"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// `preview` as a preview_t message's bytes, stamped `utime` (the frame's arrival, epoch
/// microseconds), at most options.max_bytes: while it is larger the JPEG's quality drops and
/// then the points are thinned. Empty, with one line in `error`, when the image cannot be
/// encoded or nothing fits.
std::vector<std::uint8_t> EncodePreview(const Preview& preview, std::int64_t utime,
                                        const PreviewOptions& options, std::string* error);

/// A preview_t as a viewer uses it: the JPEG as it came, the points uncompressed.
struct DecodedPreview {
  std::int64_t utime = 0, seq = 0;
  int width = 0, height = 0;
  float fx = 0, fy = 0, cx = 0, cy = 0;
  bool colour = false;
  std::string image_format;
  std::vector<std::uint8_t> image;
  int num_points = 0;
  /// num_points x (int16 x, y, z) little-endian millimetres, then num_points uint8 tags
  /// (preview_t.lcm says what a tag means).
  std::vector<std::uint8_t> points;
  std::vector<std::array<float, 3>> instance_centroids;
  std::array<double, 3> box_trans{};
  std::array<double, 4> box_quat{};
  std::vector<std::array<float, 3>> level_min, level_max;
  std::array<double, 3> fovea{};
  float growth = 0;
  bool has_truth = false;
  std::array<float, 3> truth_centroid{};
};

/// Decodes a preview_t, its layout checked before lcm-gen's decoder sizes anything and its
/// points checked to inflate to exactly num_points' block (at most 20000 points). nullopt with
/// why not, in one line.
std::optional<DecodedPreview> DecodePreview(const void* data, std::size_t size, std::string* why);

}  // namespace saccade
