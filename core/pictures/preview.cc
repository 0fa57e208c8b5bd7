#include "core/pictures/preview.h"

#include "core/fail.h"
#include "core/foveation.h"
#include "core/pictures/overlay.h"
#include "core/verification.h"

#include <algorithm>
#include <cmath>

namespace saccade {

namespace {

bool InRange(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

/// Metres to whole millimetres, clamped to int16.
std::int16_t Mm(float m) {
  return static_cast<std::int16_t>(std::clamp(std::lround(m * 1000.0f), -32767L, 32767L));
}

void AppendMm(const Eigen::Vector3f& p, std::vector<std::int16_t>* out) {
  out->push_back(Mm(p.x()));
  out->push_back(Mm(p.y()));
  out->push_back(Mm(p.z()));
}

/// Every ceil(n / limit)-th of n items: at most `limit`, spread evenly.
std::size_t Stride(std::size_t n, int limit) {
  if (limit <= 0) return 0;
  return std::max<std::size_t>(
      1, (n + static_cast<std::size_t>(limit) - 1) / static_cast<std::size_t>(limit));
}

}  // namespace

bool PreviewOptions::IsValid(std::string* error) const {
  if (!InRange(rate_hz, 1e-3, 30)) return Fail(error, "rate_hz must be in [0.001, 30]");
  if (image_step < 1 || image_step > 8) return Fail(error, "image_step must be in [1, 8]");
  if (jpeg_quality < 10 || jpeg_quality > 95)
    return Fail(error, "jpeg_quality must be in [10, 95]");
  if (max_points < 0 || max_points > 20000) return Fail(error, "max_points must be in [0, 20000]");
  if (model_points < 0 || model_points > 2000)
    return Fail(error, "model_points must be in [0, 2000]");
  if (max_bytes < 8000 || max_bytes > 1000000)
    return Fail(error, "max_bytes must be in [8000, 1000000]");
  return true;
}

Preview MakePreview(const Cloud& scene, const CameraIntrinsics& intrinsics,
                    const FoveaGeometry& geometry, const std::vector<Detection>& instances,
                    const PreviewModels& models, const PreviewOptions& options) {
  Preview p;
  const int step = std::max(1, options.image_step);
  const bool organized = scene.height > 1 &&
                         scene.width == static_cast<unsigned>(intrinsics.width) &&
                         scene.height == static_cast<unsigned>(intrinsics.height);
  if (organized) {
    const int w = intrinsics.width / step, h = intrinsics.height / step;
    p.intrinsics = intrinsics;
    p.intrinsics.width = w;
    p.intrinsics.height = h;
    // Pixel (u, v) of the small image is pixel (u s, v s) of the frame: centres scale about
    // the frame's first pixel centre.
    p.intrinsics.fx = intrinsics.fx / step;
    p.intrinsics.fy = intrinsics.fy / step;
    p.intrinsics.cx = intrinsics.cx / step;
    p.intrinsics.cy = intrinsics.cy / step;
    p.colour = HasColour(scene);
    p.rgb = SceneImage(scene, intrinsics, step, p.colour).data;
  }

  // The foveated cloud's points, each with its level, thinned evenly over the image.
  std::vector<std::pair<int, std::uint8_t>> kept;  // (index in scene, level)
  if (options.max_points > 0) {
    // An organized scene is visited on the image's own grid, a loose one whole.
    const std::size_t columns = organized ? scene.width : scene.size();
    const std::size_t rows = organized ? scene.height : 1;
    const std::size_t grid = organized ? static_cast<std::size_t>(step) : 1;
    for (std::size_t v = 0; v < rows; v += grid)
      for (std::size_t u = 0; u < columns; u += grid) {
        const std::size_t i = v * columns + u;
        const PointT& q = scene[i];
        if (!FinitePoint(q)) continue;
        const int level = LevelOf(geometry, q.getVector3fMap());
        if (level >= 0) kept.emplace_back(static_cast<int>(i), static_cast<std::uint8_t>(level));
      }
    const std::size_t every = Stride(kept.size(), options.max_points);
    for (std::size_t k = 0; k < kept.size(); k += every) {
      AppendMm(scene[kept[k].first].getVector3fMap(), &p.points_mm);
      p.levels.push_back(kept[k].second);
    }
  }

  for (std::size_t i = 0; i < instances.size() && i < kPreviewMaxInstances; ++i) {
    const Detection& d = instances[i];
    p.instance_centroids_m.push_back(d.centroid_m);
    const Cloud* model = d.model >= 0 && static_cast<std::size_t>(d.model) < models.size()
                             ? models[d.model]
                             : nullptr;
    if (!model || model->empty() || options.model_points <= 0) continue;
    const Eigen::Affine3f X_SM(d.model_to_scene);
    const std::size_t every = Stride(model->size(), options.model_points);
    for (std::size_t k = 0; k < model->size(); k += every) {
      if (p.levels.size() + p.instance_of_point.size() >= kPreviewMaxPoints) break;
      if (!FinitePoint((*model)[k])) continue;
      AppendMm(X_SM * (*model)[k].getVector3fMap(), &p.instance_points_mm);
      p.instance_of_point.push_back(static_cast<std::uint8_t>(i));
    }
  }

  p.camera_from_box = geometry.box_from_camera.inverse();
  p.level_boxes = geometry.levels;
  return p;
}

}  // namespace saccade
