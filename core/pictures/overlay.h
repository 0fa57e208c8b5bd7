// Overlays drawn into an 8-bit RGB image: the scene as its camera saw it, a model's points and
// its oriented box at a pose, and short labels in a built-in 5x7 bitmap font. Pure pixel work
// (no I/O): daemon/eval/overlays.h writes the result as PNG. Images are row-major, (u, v) =
// (column, row), pixel centres at integer coordinates as in core/camera.h.
#pragma once

#include "core/camera.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

// The scene cloud is taken by reference only: PCL's headers stay out of this one.
namespace pcl {
struct PointXYZRGBA;
template <typename PointT>
class PointCloud;
}  // namespace pcl

namespace saccade {

/// An 8-bit colour.
struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
  bool operator!=(const Rgb& o) const { return !(*this == o); }
};

/// An 8-bit RGB image, row-major, 3 bytes a pixel. Writes outside it are dropped, so callers
/// draw without clipping.
struct RgbCanvas {
  int width = 0, height = 0;
  std::vector<std::uint8_t> data;  // width * height * 3 bytes: r, g, b

  RgbCanvas() = default;
  RgbCanvas(int w, int h, Rgb fill = {});
  bool Inside(int u, int v) const { return u >= 0 && v >= 0 && u < width && v < height; }
  /// Precondition: Inside(u, v).
  Rgb At(int u, int v) const;
  /// Does nothing outside the image.
  void Set(int u, int v, Rgb c);
};

/// A box of any orientation, in the frame its owner names: centre (metres), axes (columns,
/// orthonormal) and the half sizes along them (metres).
struct OrientedBox {
  Eigen::Vector3f centre_m = Eigen::Vector3f::Zero();
  Eigen::Matrix3f axes = Eigen::Matrix3f::Identity();
  Eigen::Vector3f half_size_m = Eigen::Vector3f::Zero();

  /// The 8 corners; corner i is at +half along axis k when bit k of i is set, else at -half.
  std::array<Eigen::Vector3f, 8> Corners() const;
  /// The same box in the frame X_BA takes this box's frame A to.
  OrientedBox Transformed(const Eigen::Matrix4f& X_BA) const;
};

/// The box along the points' principal axes that holds every finite point (a zero box at the
/// origin when there is none).
OrientedBox FitOrientedBox(const std::vector<Eigen::Vector3f>& points);

/// The scene as its camera saw it. An organized cloud gives one pixel per point (its colour,
/// held by Kinect clouds even where depth is missing); an unorganized cloud is projected with
/// `camera` (the nearest point wins a pixel) onto a black image of camera.width x height. A
/// cloud without colour (HasColour) is shaded by depth instead (near is bright). `step` > 1 keeps
/// every step-th pixel of an organized cloud each way (pixel (u, v) is the cloud's
/// (u step, v step)); an unorganized cloud is always drawn whole. `coloured`: HasColour(scene),
/// when the caller has it already (it reads every point).
RgbCanvas SceneImage(const pcl::PointCloud<pcl::PointXYZRGBA>& scene,
                     const CameraIntrinsics& camera, int step = 1,
                     std::optional<bool> coloured = std::nullopt);

/// A model as a picture: its finite points seen from `panels` viewpoints around its centre (each
/// a square panel of `panel_px`, side by side on white: turned about the camera frame's vertical
/// axis in equal steps, from 25 degrees above; the first from where a captured model's camera
/// stood), nearer points over farther ones, each in its colour or, without colour, grey, darker
/// with depth. Each panel is labelled with its turn.
RgbCanvas ModelImage(const pcl::PointCloud<pcl::PointXYZRGBA>& model, int panels, int panel_px);

/// A filled square of side 2 * radius_px + 1 centred on pixel (u, v).
void DrawDot(int u, int v, int radius_px, Rgb colour, RgbCanvas* canvas);
/// A line from pixel a to pixel b, `thickness_px` wide (clipped to the image first, so far
/// away end points cost nothing).
void DrawLine(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Rgb colour, int thickness_px,
              RgbCanvas* canvas);
/// The segment between two camera-frame points (metres), the part behind the camera cut off.
void DrawSegment(const Eigen::Vector3f& a_C, const Eigen::Vector3f& b_C,
                 const CameraIntrinsics& camera, Rgb colour, int thickness_px, RgbCanvas* canvas);
/// The 12 edges of a camera-frame box.
void DrawBox(const OrientedBox& box_C, const CameraIntrinsics& camera, Rgb colour, int thickness_px,
             RgbCanvas* canvas);
/// Each camera-frame point in front of the camera as a dot; returns how many landed in the
/// image.
int DrawPoints(const std::vector<Eigen::Vector3f>& points_C, const CameraIntrinsics& camera,
               Rgb colour, int radius_px, RgbCanvas* canvas);

/// Pixels a line of `text` takes at `scale` (each glyph 5x7 pixels plus a column of space,
/// times scale).
Eigen::Vector2i TextSize(const std::string& text, int scale);
/// `text` with its top-left corner at pixel (u, v) on a filled `background` one pixel wider
/// all round. Letters are drawn as capitals; a character without a glyph is drawn as '?'.
void DrawText(const std::string& text, int u, int v, int scale, Rgb colour, Rgb background,
              RgbCanvas* canvas);

/// One model drawn at a pose: its points, its oriented box and a label above it.
struct OverlayMark {
  Eigen::Matrix4f model_to_scene = Eigen::Matrix4f::Identity();  // X_SM, metres
  Rgb colour;
  std::string label;  // e.g. "#0 0.93"; none when empty
};

/// Draws each mark: the model's points (`model_points_M`, model frame) moved by its pose, the
/// model's box `box_M` likewise, and its label at the top-left of the points' 2D box (inside
/// the image). Marks are drawn in order, a later one over an earlier one; labels over all.
void DrawMarks(const std::vector<Eigen::Vector3f>& model_points_M, const OrientedBox& box_M,
               const std::vector<OverlayMark>& marks, const CameraIntrinsics& camera,
               RgbCanvas* canvas);

}  // namespace saccade
