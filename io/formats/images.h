// Depth and colour images on disk: 16-bit PNG/TIFF depth in millimetres, 8-bit RGB PNG/TIFF,
// and the intrinsics file beside them. No PCL here, so the OpenNI2 driver can use it too.
#pragma once

#include "core/camera.h"

#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

/// A row-major image of `channels` samples per pixel.
template <typename T>
struct Image {
  int width = 0, height = 0, channels = 1;
  std::vector<T> data;
};
using DepthImage = Image<std::uint16_t>;  // millimetres, 0 = no return
using RgbImage = Image<std::uint8_t>;     // 3 channels

/// Reads a single-channel 16-bit PNG or TIFF (chosen by extension). False with `error` =
/// "PATH: reason" otherwise.
bool ReadDepthImage(const std::string& path, DepthImage* image, std::string* error);
/// Reads an 8-bit RGB or RGBA PNG or TIFF as RGB.
bool ReadRgbImage(const std::string& path, RgbImage* image, std::string* error);
bool WriteDepthPng(const std::string& path, const DepthImage& image, std::string* error);
bool WriteRgbPng(const std::string& path, const RgbImage& image, std::string* error);

/// The depth images of a folder, in name order: PNG or TIFF files whose names contain "depth".
/// Empty when there are none or the folder cannot be read.
std::vector<std::string> ListDepthImages(const std::string& dir);
/// The colour image beside a depth image: its name with the last "depth" made "rgb"; empty
/// when no such file exists.
std::string RgbPartner(const std::string& depth_path);

/// Pinhole intrinsics as written beside depth images: one "key: value" per line for fx, fy,
/// cx, cy (pixels), width and height. Plain numbers, so the file is also valid YAML.
struct IntrinsicsFile {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;

  CameraIntrinsics Camera() const {
    CameraIntrinsics k;
    k.fx = fx, k.fy = fy, k.cx = cx, k.cy = cy, k.width = width, k.height = height;
    return k;
  }
};
bool ReadIntrinsicsFile(const std::string& path, IntrinsicsFile* intrinsics, std::string* error);
bool WriteIntrinsicsFile(const std::string& path, const IntrinsicsFile& intrinsics,
                         std::string* error);

/// The colour camera of a two-camera sensor (colour.yaml beside depth images, or a spec's
/// calibration= file), in the same "key: value" form: its intrinsics (fx, fy, cx, cy, width,
/// height, pixels) and its place in the depth camera's frame: tx, ty, tz (its origin, metres)
/// and rx, ry, rz (its rotation, a rotation vector in radians), each 0 when absent.
struct ColourCameraFile {
  IntrinsicsFile intrinsics;
  double t[3] = {0, 0, 0};
  double r[3] = {0, 0, 0};
};
inline constexpr char kColourCameraFileName[] = "colour.yaml";
bool ReadColourCameraFile(const std::string& path, ColourCameraFile* colour, std::string* error);
bool WriteColourCameraFile(const std::string& path, const ColourCameraFile& colour,
                           std::string* error);

}  // namespace saccade
