#include "io/lcm/preview.h"

#include "io/lcm/lcm_log.h"

#include <saccade/preview_t.hpp>

#include <jpeglib.h>
#include <zlib.h>

#include <algorithm>
#include <csetjmp>
#include <cstring>

namespace saccade {
namespace {

constexpr std::uint8_t kInstanceTag = 128;

// libjpeg reports errors through a callback that must not return: jump back to the encoder.
struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
};

void JpegFail(j_common_ptr cinfo) {
  std::longjmp(reinterpret_cast<JpegError*>(cinfo->err)->jump, 1);
}

/// The RGB image as JPEG; empty when libjpeg fails.
std::vector<std::uint8_t> Jpeg(const std::vector<std::uint8_t>& rgb, int width, int height,
                               int quality) {
  std::vector<std::uint8_t> out;
  if (width <= 0 || height <= 0 ||
      rgb.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3)
    return out;
  jpeg_compress_struct cinfo{};
  JpegError error{};
  cinfo.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = JpegFail;
  unsigned char* buffer = nullptr;
  unsigned long size = 0;  // NOLINT(runtime/int): libjpeg's type
  if (setjmp(error.jump)) {
    jpeg_destroy_compress(&cinfo);
    std::free(buffer);
    return {};
  }
  jpeg_create_compress(&cinfo);
  jpeg_mem_dest(&cinfo, &buffer, &size);
  cinfo.image_width = static_cast<JDIMENSION>(width);
  cinfo.image_height = static_cast<JDIMENSION>(height);
  cinfo.input_components = 3;
  cinfo.in_color_space = JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(
        &rgb[static_cast<std::size_t>(cinfo.next_scanline) * static_cast<std::size_t>(width) * 3]);
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  out.assign(buffer, buffer + size);
  jpeg_destroy_compress(&cinfo);
  std::free(buffer);
  return out;
}

void PutInt16(std::vector<std::uint8_t>* out, std::int16_t v) {
  const auto u = static_cast<std::uint16_t>(v);
  out->push_back(static_cast<std::uint8_t>(u & 0xff));
  out->push_back(static_cast<std::uint8_t>(u >> 8));
}

/// The points block (preview_t.lcm), every `every`-th of the cloud's and all the instances'.
std::vector<std::uint8_t> PointsBlock(const Preview& p, std::size_t every, int* count) {
  std::vector<std::uint8_t> xyz, tags;
  for (std::size_t i = 0; i < p.levels.size(); i += every) {
    for (int c = 0; c < 3; ++c) PutInt16(&xyz, p.points_mm[3 * i + c]);
    tags.push_back(p.levels[i]);
  }
  for (std::size_t i = 0; i < p.instance_of_point.size(); ++i) {
    for (int c = 0; c < 3; ++c) PutInt16(&xyz, p.instance_points_mm[3 * i + c]);
    tags.push_back(
        static_cast<std::uint8_t>(kInstanceTag + std::min<int>(p.instance_of_point[i], 127)));
  }
  *count = static_cast<int>(tags.size());
  xyz.insert(xyz.end(), tags.begin(), tags.end());
  return xyz;
}

std::vector<std::uint8_t> Deflate(const std::vector<std::uint8_t>& raw) {
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> out(size);
  if (compress2(out.data(), &size, raw.data(), static_cast<uLong>(raw.size()), 6) != Z_OK)
    return {};
  out.resize(size);
  return out;
}

std::int16_t Int16(const unsigned char* p) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>((p[0] << 8) | p[1]));
}

bool Reject(std::string* why, const std::string& text) {
  if (why) *why = "preview_t: " + text;
  return false;
}

/// preview_t's wire layout walked before lcm-gen's decoder trusts its counts.
bool PreviewFits(const unsigned char* d, std::size_t size, std::string* why) {
  std::size_t at = 8;  // the type hash
  if (!LcmFieldsFit(d, size, &at, {8, 8, 2, 2, 4, 4, 4, 4, 1, kLcmString, 4}))
    return Reject(why, "truncated or a bad string before the image");
  const std::int32_t image_size = LcmInt32(d + at - 4);
  if (image_size < 0 || static_cast<std::size_t>(image_size) > size - at)
    return Reject(why, "image_size " + std::to_string(image_size) + " is beyond the message");
  at += static_cast<std::size_t>(image_size);
  if (!LcmFieldsFit(d, size, &at, {4, 4})) return Reject(why, "truncated before the points");
  const std::int32_t num_points = LcmInt32(d + at - 8), points_size = LcmInt32(d + at - 4);
  if (num_points < 0 || num_points > kPreviewMaxPoints)
    return Reject(why, "num_points " + std::to_string(num_points) + " is not in [0, 20000]");
  if (points_size < 0 || static_cast<std::size_t>(points_size) > size - at)
    return Reject(why, "points_size " + std::to_string(points_size) + " is beyond the message");
  at += static_cast<std::size_t>(points_size);
  if (!LcmFieldsFit(d, size, &at, {2})) return Reject(why, "truncated before the instances");
  const std::int16_t instances = Int16(d + at - 2);
  if (instances < 0 || static_cast<std::size_t>(instances) * 12 > size - at)
    return Reject(why, "num_instances " + std::to_string(instances) + " is beyond the message");
  at += static_cast<std::size_t>(instances) * 12;
  if (!LcmFieldsFit(d, size, &at, {24, 32, 1})) return Reject(why, "truncated before the boxes");
  const auto levels = static_cast<std::int8_t>(d[at - 1]);
  if (levels < 0 || static_cast<std::size_t>(levels) * 24 > size - at)
    return Reject(why, "num_levels " + std::to_string(levels) + " is beyond the message");
  at += static_cast<std::size_t>(levels) * 24;
  if (!LcmFieldsFit(d, size, &at, {24, 4, 1, 12}) || at != size)
    return Reject(why, "its length does not match its fields");
  return true;
}

template <std::size_t N, typename T>
std::array<T, N> ArrayOf(const T (&v)[N]) {
  std::array<T, N> out{};
  std::copy(v, v + N, out.begin());
  return out;
}

}  // namespace

std::vector<std::uint8_t> EncodePreview(const Preview& preview, std::int64_t utime,
                                        const PreviewOptions& options, std::string* error) {
  saccade::preview_t m{};
  m.utime = utime;
  m.seq = preview.seq;
  m.width = static_cast<std::int16_t>(preview.intrinsics.width);
  m.height = static_cast<std::int16_t>(preview.intrinsics.height);
  m.fx = static_cast<float>(preview.intrinsics.fx);
  m.fy = static_cast<float>(preview.intrinsics.fy);
  m.cx = static_cast<float>(preview.intrinsics.cx);
  m.cy = static_cast<float>(preview.intrinsics.cy);
  m.colour = preview.colour;
  m.image_format = "jpeg";
  m.num_instances = static_cast<std::int16_t>(
      std::min<std::size_t>(preview.instance_centroids_m.size(), kPreviewMaxInstances));
  for (int i = 0; i < m.num_instances; ++i) {
    const Eigen::Vector3f& c = preview.instance_centroids_m[static_cast<std::size_t>(i)];
    m.instance_centroid.push_back({c.x(), c.y(), c.z()});
  }
  const Eigen::Vector3f t = preview.camera_from_box.translation();
  const Eigen::Quaternionf q(preview.camera_from_box.rotation());
  for (int c = 0; c < 3; ++c) m.box_trans[c] = t[c], m.fovea[c] = preview.fovea_m[c];
  m.box_quat[0] = q.w(), m.box_quat[1] = q.x(), m.box_quat[2] = q.y(), m.box_quat[3] = q.z();
  m.num_levels = static_cast<std::int8_t>(std::min<std::size_t>(preview.level_boxes.size(), 127));
  for (int k = 0; k < m.num_levels; ++k) {
    const Box& b = preview.level_boxes[static_cast<std::size_t>(k)];
    m.level_min.push_back({b.min.x(), b.min.y(), b.min.z()});
    m.level_max.push_back({b.max.x(), b.max.y(), b.max.z()});
  }
  m.growth = preview.growth_m;
  m.has_truth = preview.has_truth;
  for (int c = 0; c < 3; ++c) m.truth_centroid[c] = preview.truth_centroid_m[c];

  // Quality first, then the cloud's points, until the message fits.
  int quality = options.jpeg_quality, encoded_quality = -1;
  std::size_t every = 1;
  for (int attempt = 0; attempt < 24; ++attempt) {
    if (!preview.rgb.empty() && quality != encoded_quality) {  // the image again only if changed
      encoded_quality = quality;
      m.image = Jpeg(preview.rgb, preview.intrinsics.width, preview.intrinsics.height, quality);
      if (m.image.empty()) {
        if (error) *error = "preview: the image could not be encoded as JPEG";
        return {};
      }
    }
    m.image_size = static_cast<std::int32_t>(m.image.size());
    m.points = Deflate(PointsBlock(preview, every, &m.num_points));
    m.points_size = static_cast<std::int32_t>(m.points.size());
    const int size = m.getEncodedSize();
    if (m.num_points > kPreviewMaxPoints && every < preview.levels.size()) {
      every *= 2;  // more points than a viewer takes: thin the cloud first
      continue;
    }
    if (size <= options.max_bytes && m.num_points <= kPreviewMaxPoints) {
      std::vector<std::uint8_t> out(static_cast<std::size_t>(size));
      if (m.encode(out.data(), 0, size) == size) return out;
      break;
    }
    if (quality > 20) {
      quality = std::max(20, quality - 15);
    } else if (every < preview.levels.size()) {
      every *= 2;
    } else {
      break;
    }
  }
  if (error)
    *error = "preview: nothing fits in max_bytes " + std::to_string(options.max_bytes) +
             " (raise preview.max_bytes or image_step)";
  return {};
}

std::optional<DecodedPreview> DecodePreview(const void* data, std::size_t size, std::string* why) {
  const auto* d = static_cast<const unsigned char*>(data);
  if (size > static_cast<std::size_t>(INT32_MAX))
    return Reject(why, "larger than 2 GB"), std::nullopt;
  if (!PreviewFits(d, size, why)) return std::nullopt;
  saccade::preview_t m;
  if (m.decode(data, 0, static_cast<int>(size)) < 0) {
    Reject(why, "not a preview_t (its type hash differs)");
    return std::nullopt;
  }
  if (m.width < 0 || m.height < 0) {
    Reject(why, "negative image size");
    return std::nullopt;
  }
  DecodedPreview p;
  p.utime = m.utime;
  p.seq = m.seq;
  p.width = m.width;
  p.height = m.height;
  p.fx = m.fx, p.fy = m.fy, p.cx = m.cx, p.cy = m.cy;
  p.colour = m.colour;
  p.image_format = m.image_format;
  p.image = std::move(m.image);
  p.num_points = m.num_points;
  // The block inflates to exactly 7 bytes a point; anything else is refused.
  const std::size_t expected = static_cast<std::size_t>(m.num_points) * 7;
  p.points.resize(expected);
  uLongf inflated = static_cast<uLongf>(expected);
  if (m.num_points > 0 && (uncompress(p.points.data(), &inflated, m.points.data(),
                                      static_cast<uLong>(m.points.size())) != Z_OK ||
                           inflated != expected)) {
    Reject(why, "its points do not inflate to " + std::to_string(m.num_points) + " points");
    return std::nullopt;
  }
  for (const auto& c : m.instance_centroid) p.instance_centroids.push_back({c[0], c[1], c[2]});
  p.box_trans = ArrayOf(m.box_trans);
  p.box_quat = ArrayOf(m.box_quat);
  for (const auto& v : m.level_min) p.level_min.push_back({v[0], v[1], v[2]});
  for (const auto& v : m.level_max) p.level_max.push_back({v[0], v[1], v[2]});
  p.fovea = ArrayOf(m.fovea);
  p.growth = m.growth;
  p.has_truth = m.has_truth;
  p.truth_centroid = ArrayOf(m.truth_centroid);
  return p;
}

}  // namespace saccade
