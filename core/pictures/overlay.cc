#include "core/pictures/overlay.h"

#include "core/check.h"
#include "core/surface_views.h"
#include "core/types.h"
#include "core/verification.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace saccade {
namespace {

// Points closer to the camera than this are behind it for drawing (metres).
constexpr float kNearM = 0.01f;

// A 5x7 glyph: seven rows, bit 4 the leftmost column.
struct Glyph {
  char c;
  std::uint8_t rows[7];
};

// Capitals, digits and the punctuation labels use; enough for "#3 0.93", "TRUTH", "FALSE 12".
constexpr Glyph kFont[] = {
    {' ', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00}},
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
    {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}},
    {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
    {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}},
    {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
    {'#', {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'=', {0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
    {'?', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}},
};
constexpr int kGlyphW = 5, kGlyphH = 7;

const Glyph& GlyphOf(char c) {
  if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  for (const Glyph& g : kFont)
    if (g.c == c) return g;
  return GlyphOf('?');
}

Eigen::Vector3f Apply(const Eigen::Matrix4f& X, const Eigen::Vector3f& p) {
  return X.topLeftCorner<3, 3>() * p + X.topRightCorner<3, 1>();
}

void FillRect(int u0, int v0, int u1, int v1, Rgb colour, RgbCanvas* canvas) {
  for (int v = std::max(0, v0); v <= std::min(canvas->height - 1, v1); ++v)
    for (int u = std::max(0, u0); u <= std::min(canvas->width - 1, u1); ++u)
      canvas->Set(u, v, colour);
}

// Liang-Barsky: cuts segment a-b to the rectangle [lo, hi]; false when nothing is left.
bool Clip(Eigen::Vector2d* a, Eigen::Vector2d* b, const Eigen::Vector2d& lo,
          const Eigen::Vector2d& hi) {
  const Eigen::Vector2d d = *b - *a;
  double t0 = 0, t1 = 1;
  for (int k = 0; k < 2; ++k) {
    for (const auto& [p, q] :
         {std::pair{-d[k], (*a)[k] - lo[k]}, std::pair{d[k], hi[k] - (*a)[k]}}) {
      if (p == 0) {
        if (q < 0) return false;
        continue;
      }
      const double t = q / p;
      if (p < 0)
        t0 = std::max(t0, t);
      else
        t1 = std::min(t1, t);
      if (t0 > t1) return false;
    }
  }
  const Eigen::Vector2d start = *a;
  *a = start + t0 * d;
  *b = start + t1 * d;
  return true;
}

Rgb DepthShade(float z_m, float near_m, float far_m) {
  const float t = far_m > near_m ? (z_m - near_m) / (far_m - near_m) : 0.0f;
  const auto grey = static_cast<std::uint8_t>(std::lround(230.0f - 180.0f * t));
  return {grey, grey, grey};
}

}  // namespace

RgbCanvas::RgbCanvas(int w, int h, Rgb fill) : width(w), height(h) {
  SACCADE_CHECK(w >= 0 && h >= 0, "an image cannot have a negative size");
  data.resize(static_cast<std::size_t>(w) * h * 3);
  for (std::size_t i = 0; i < data.size(); i += 3) {
    data[i] = fill.r;
    data[i + 1] = fill.g;
    data[i + 2] = fill.b;
  }
}

Rgb RgbCanvas::At(int u, int v) const {
  SACCADE_CHECK(Inside(u, v), "pixel outside the image");
  const std::size_t i = (static_cast<std::size_t>(v) * width + u) * 3;
  return {data[i], data[i + 1], data[i + 2]};
}

void RgbCanvas::Set(int u, int v, Rgb c) {
  if (!Inside(u, v)) return;
  const std::size_t i = (static_cast<std::size_t>(v) * width + u) * 3;
  data[i] = c.r;
  data[i + 1] = c.g;
  data[i + 2] = c.b;
}

std::array<Eigen::Vector3f, 8> OrientedBox::Corners() const {
  std::array<Eigen::Vector3f, 8> corners;
  for (int i = 0; i < 8; ++i) {
    Eigen::Vector3f p = centre_m;
    for (int k = 0; k < 3; ++k) p += ((i >> k) & 1 ? 1.0f : -1.0f) * half_size_m[k] * axes.col(k);
    corners[i] = p;
  }
  return corners;
}

OrientedBox OrientedBox::Transformed(const Eigen::Matrix4f& X_BA) const {
  OrientedBox b = *this;
  b.centre_m = Apply(X_BA, centre_m);
  b.axes = X_BA.topLeftCorner<3, 3>() * axes;
  return b;
}

OrientedBox FitOrientedBox(const std::vector<Eigen::Vector3f>& points) {
  OrientedBox box;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int n = 0;
  for (const Eigen::Vector3f& p : points)
    if (p.allFinite()) mean += p.cast<double>(), ++n;
  if (n == 0) return box;
  mean /= n;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3f& p : points)
    if (p.allFinite()) {
      const Eigen::Vector3d d = p.cast<double>() - mean;
      covariance += d * d.transpose();
    }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d axes = solver.eigenvectors();
  if (axes.determinant() < 0) axes.col(0) = -axes.col(0);  // right-handed
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const Eigen::Vector3f& p : points)
    if (p.allFinite()) {
      const Eigen::Vector3d q = axes.transpose() * (p.cast<double>() - mean);
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  box.axes = axes.cast<float>();
  box.centre_m = (mean + axes * (0.5 * (lo + hi))).cast<float>();
  box.half_size_m = (0.5 * (hi - lo)).cast<float>();
  return box;
}

RgbCanvas SceneImage(const Cloud& scene, const CameraIntrinsics& camera, int step,
                     std::optional<bool> has_colour) {
  const bool coloured = has_colour ? *has_colour : HasColour(scene);
  float near_m = std::numeric_limits<float>::max(), far_m = 0;
  for (const PointT& p : scene.points)
    if (FinitePoint(p) && p.z > 0) near_m = std::min(near_m, p.z), far_m = std::max(far_m, p.z);
  const auto shade = [&](const PointT& p) {
    if (coloured) return Rgb{p.r, p.g, p.b};
    return FinitePoint(p) && p.z > 0 ? DepthShade(p.z, near_m, far_m) : Rgb{};
  };
  if (scene.height > 1) {
    const int s = std::max(1, step);
    RgbCanvas canvas(static_cast<int>(scene.width) / s, static_cast<int>(scene.height) / s);
    for (int v = 0; v < canvas.height; ++v)
      for (int u = 0; u < canvas.width; ++u) canvas.Set(u, v, shade(scene.at(u * s, v * s)));
    return canvas;
  }
  RgbCanvas canvas(camera.width, camera.height);
  std::vector<float> depth(static_cast<std::size_t>(camera.width) * camera.height,
                           std::numeric_limits<float>::max());
  for (const PointT& p : scene.points) {
    if (!FinitePoint(p) || p.z < kNearM) continue;
    const Eigen::Vector2d uv = camera.Project(p.getVector3fMap());
    const long u = std::lround(uv.x()), v = std::lround(uv.y());
    if (!canvas.Inside(static_cast<int>(u), static_cast<int>(v))) continue;
    float& z = depth[static_cast<std::size_t>(v) * camera.width + u];
    if (p.z >= z) continue;
    z = p.z;
    canvas.Set(static_cast<int>(u), static_cast<int>(v), shade(p));
  }
  return canvas;
}

RgbCanvas ModelImage(const Cloud& model, int panels, int panel_px) {
  panels = std::max(1, panels);
  panel_px = std::max(16, panel_px);
  RgbCanvas canvas(panels * panel_px, panel_px, Rgb{255, 255, 255});
  std::vector<const PointT*> points;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (const PointT& p : model.points)
    if (FinitePoint(p)) {
      points.push_back(&p);
      lo = lo.cwiseMin(p.getVector3fMap());
      hi = hi.cwiseMax(p.getVector3fMap());
    }
  if (points.empty()) return canvas;
  const bool coloured = HasColour(model);
  const Eigen::Vector3f centre = (lo + hi) / 2;
  const float radius = std::max(1e-3f, (hi - lo).norm() / 2);
  // The first viewpoint: where a captured model's camera stood (its sensor origin, when outside
  // the model), else in front along -z, as a camera's frame would have it.
  Eigen::Vector3f front = model.sensor_origin_.head<3>() - centre;
  if (!((front.array().abs() > (hi - lo).array() / 2).any()) || !front.allFinite())
    front = -Eigen::Vector3f::UnitZ();
  front.y() = 0;
  if (front.norm() < 1e-6f) front = -Eigen::Vector3f::UnitZ();
  front.normalize();
  const float distance = 4 * radius;
  CameraIntrinsics k;
  k.width = k.height = panel_px;
  k.fx = k.fy = 0.45 * panel_px * distance / radius;  // the bounding sphere within 90%
  k.cx = k.cy = (panel_px - 1) / 2.0;
  // Spacing between neighbours, from the points' count over the surface of the sphere's half.
  const float spacing = std::sqrt(2 * float(M_PI) * radius * radius / float(points.size()));
  const int dot = std::max(0, int(std::lround(0.8 * k.fx * spacing / distance)));
  constexpr float kAbove = 25.0f * float(M_PI) / 180.0f;
  for (int panel = 0; panel < panels; ++panel) {
    const float yaw = 2 * float(M_PI) * float(panel) / float(panels);
    const Eigen::Vector3f around = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitY()) * front;
    const Eigen::Vector3f dir =
        std::cos(kAbove) * around - std::sin(kAbove) * Eigen::Vector3f::UnitY();
    const Eigen::Matrix4f to_camera = LookAt(centre + distance * dir, centre).inverse();
    std::vector<std::size_t> order(points.size());
    std::vector<Eigen::Vector3f> in_camera(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      in_camera[i] = (to_camera * points[i]->getVector3fMap().homogeneous()).head<3>();
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return in_camera[a].z() > in_camera[b].z(); });
    RgbCanvas view(panel_px, panel_px, Rgb{255, 255, 255});
    for (std::size_t i : order) {  // far to near: nearer dots cover farther ones
      const Eigen::Vector3f& q = in_camera[i];
      const float light = std::clamp(0.55f + 0.45f * (distance - q.z()) / radius, 0.1f, 1.0f);
      const PointT& p = *points[i];
      const Rgb base = coloured ? Rgb{p.r, p.g, p.b} : Rgb{200, 200, 200};
      const Rgb c{std::uint8_t(base.r * light), std::uint8_t(base.g * light),
                  std::uint8_t(base.b * light)};
      const Eigen::Vector2d uv = k.Project(q);
      DrawDot(int(std::lround(uv.x())), int(std::lround(uv.y())), dot, c, &view);
    }
    DrawText(std::to_string(int(std::lround(yaw * 180 / M_PI))) + " DEG", 4, 4, 2, Rgb{0, 0, 0},
             Rgb{255, 255, 255}, &view);
    for (int v = 0; v < panel_px; ++v)
      for (int u = 0; u < panel_px; ++u) canvas.Set(panel * panel_px + u, v, view.At(u, v));
  }
  return canvas;
}

void DrawDot(int u, int v, int radius_px, Rgb colour, RgbCanvas* canvas) {
  FillRect(u - radius_px, v - radius_px, u + radius_px, v + radius_px, colour, canvas);
}

void DrawLine(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Rgb colour, int thickness_px,
              RgbCanvas* canvas) {
  if (!a.allFinite() || !b.allFinite()) return;
  const int radius = std::max(0, (thickness_px - 1) / 2);
  Eigen::Vector2d p = a, q = b;
  const Eigen::Vector2d margin = Eigen::Vector2d::Constant(radius + 1.0);
  if (!Clip(&p, &q, -margin, Eigen::Vector2d(canvas->width, canvas->height) + margin)) return;
  const int steps = static_cast<int>(std::ceil((q - p).cwiseAbs().maxCoeff()));
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2d r = steps ? p + (q - p) * (double(i) / steps) : p;
    DrawDot(static_cast<int>(std::lround(r.x())), static_cast<int>(std::lround(r.y())), radius,
            colour, canvas);
  }
}

void DrawSegment(const Eigen::Vector3f& a_C, const Eigen::Vector3f& b_C,
                 const CameraIntrinsics& camera, Rgb colour, int thickness_px, RgbCanvas* canvas) {
  Eigen::Vector3f a = a_C, b = b_C;
  if (a.z() < kNearM && b.z() < kNearM) return;
  if (a.z() < kNearM) a = b + (a - b) * ((b.z() - kNearM) / (b.z() - a.z()));
  if (b.z() < kNearM) b = a + (b - a) * ((a.z() - kNearM) / (a.z() - b.z()));
  DrawLine(camera.Project(a), camera.Project(b), colour, thickness_px, canvas);
}

void DrawBox(const OrientedBox& box_C, const CameraIntrinsics& camera, Rgb colour, int thickness_px,
             RgbCanvas* canvas) {
  const auto corners = box_C.Corners();
  // Corners i and j share an edge when they differ in one axis (one bit).
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 3; ++k) {
      const int j = i | (1 << k);
      if (j != i) DrawSegment(corners[i], corners[j], camera, colour, thickness_px, canvas);
    }
}

int DrawPoints(const std::vector<Eigen::Vector3f>& points_C, const CameraIntrinsics& camera,
               Rgb colour, int radius_px, RgbCanvas* canvas) {
  int landed = 0;
  for (const Eigen::Vector3f& p : points_C) {
    if (!p.allFinite() || p.z() < kNearM) continue;
    const Eigen::Vector2d uv = camera.Project(p);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    landed += canvas->Inside(u, v);
    DrawDot(u, v, radius_px, colour, canvas);
  }
  return landed;
}

Eigen::Vector2i TextSize(const std::string& text, int scale) {
  const int n = static_cast<int>(text.size());
  return {n == 0 ? 0 : (n * (kGlyphW + 1) - 1) * scale, kGlyphH * scale};
}

void DrawText(const std::string& text, int u, int v, int scale, Rgb colour, Rgb background,
              RgbCanvas* canvas) {
  SACCADE_CHECK(scale >= 1, "text scale must be at least 1");
  const Eigen::Vector2i size = TextSize(text, scale);
  FillRect(u - scale, v - scale, u + size.x() + scale - 1, v + size.y() + scale - 1, background,
           canvas);
  for (std::size_t i = 0; i < text.size(); ++i) {
    const Glyph& g = GlyphOf(text[i]);
    const int left = u + static_cast<int>(i) * (kGlyphW + 1) * scale;
    for (int row = 0; row < kGlyphH; ++row)
      for (int col = 0; col < kGlyphW; ++col)
        if (g.rows[row] & (0x10 >> col))
          FillRect(left + col * scale, v + row * scale, left + (col + 1) * scale - 1,
                   v + (row + 1) * scale - 1, colour, canvas);
  }
}

void DrawMarks(const std::vector<Eigen::Vector3f>& model_points_M, const OrientedBox& box_M,
               const std::vector<OverlayMark>& marks, const CameraIntrinsics& camera,
               RgbCanvas* canvas) {
  constexpr int kBoxThicknessPx = 2, kTextScale = 2;
  const Rgb kTextBackground{0, 0, 0};
  struct Label {
    const OverlayMark* mark;
    int u, v;
  };
  std::vector<Label> labels;  // drawn last, so no mark's points cover another's label
  std::vector<Eigen::Vector3f> points_C(model_points_M.size());
  for (const OverlayMark& mark : marks) {
    for (std::size_t i = 0; i < model_points_M.size(); ++i)
      points_C[i] = Apply(mark.model_to_scene, model_points_M[i]);
    DrawBox(box_M.Transformed(mark.model_to_scene), camera, mark.colour, kBoxThicknessPx, canvas);
    DrawPoints(points_C, camera, mark.colour, 0, canvas);
    if (mark.label.empty()) continue;
    // The label sits above the points' 2D box, or below it when there is no room above.
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (const Eigen::Vector3f& p : points_C)
      if (p.allFinite() && p.z() >= kNearM) {
        const Eigen::Vector2d uv = camera.Project(p);
        lo = lo.cwiseMin(uv);
        hi = hi.cwiseMax(uv);
      }
    if (lo.x() > hi.x()) continue;  // nothing in front of the camera
    const Eigen::Vector2i size = TextSize(mark.label, kTextScale);
    const int margin = kTextScale + 2;
    double v = lo.y() - size.y() - margin;
    if (v < margin) v = hi.y() + margin + 1;
    // Inside the image (at its left or top edge when the label is wider or taller than it).
    const double u =
        std::max<double>(margin, std::min<double>(lo.x(), canvas->width - size.x() - margin));
    v = std::max<double>(margin, std::min<double>(v, canvas->height - size.y() - margin));
    labels.push_back({&mark, static_cast<int>(std::lround(u)), static_cast<int>(std::lround(v))});
  }
  // A label that would cover one already placed moves down below it (the top ones first).
  std::vector<Eigen::AlignedBox2i> placed;
  for (Label& l : labels) {
    const Eigen::Vector2i size = TextSize(l.mark->label, kTextScale);
    const int pad = kTextScale + 1;
    for (bool moved = true; moved;) {
      moved = false;
      const Eigen::AlignedBox2i box(Eigen::Vector2i(l.u - pad, l.v - pad),
                                    Eigen::Vector2i(l.u + size.x() + pad, l.v + size.y() + pad));
      for (const Eigen::AlignedBox2i& other : placed)
        if (box.intersects(other) && l.v + size.y() < canvas->height) {
          l.v = other.max().y() + pad + 1;
          moved = true;
        }
    }
    placed.emplace_back(Eigen::Vector2i(l.u - pad, l.v - pad),
                        Eigen::Vector2i(l.u + size.x() + pad, l.v + size.y() + pad));
    DrawText(l.mark->label, l.u, l.v, kTextScale, l.mark->colour, kTextBackground, canvas);
  }
}

}  // namespace saccade
