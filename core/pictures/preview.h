// A small picture of one processed frame for people watching (SACCADE_PREVIEW, docs/VIEWER.md):
// the frame's image decimated, the foveated cloud's coarse points by level, each instance's
// model points at its pose, and the fovea's boxes. Pure: io/lcm/preview.cc encodes it for LCM.
#pragma once

#include "core/camera.h"
#include "core/schema.h"
#include "core/types.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

struct FoveaGeometry;

/// The `preview` section of saccaded's configuration.
struct PreviewOptions {
  bool enabled = false;    // publish PREFIX_PREVIEW
  double rate_hz = 5;      // at most this many previews a second, in (0, 30]
  int image_step = 2;      // every image_step-th pixel of every image_step-th row, in [1, 8]
  int jpeg_quality = 70;   // of the decimated image, in [10, 95]
  int max_points = 6000;   // foveated cloud points at most, in [0, 20000]
  int model_points = 400;  // of each instance's model at most, in [0, 2000]
  int max_bytes = 60000;   // a message's size at most (LCM over UDP keeps it whole), >= 8000

  bool IsValid(std::string* error) const;
  bool operator==(const PreviewOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const PreviewOptions& o) const { return !(*this == o); }
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("enabled", &enabled);
    a->Visit("rate_hz", &rate_hz);
    a->Visit("image_step", &image_step);
    a->Visit("jpeg_quality", &jpeg_quality);
    a->Visit("max_points", &max_points);
    a->Visit("model_points", &model_points);
    a->Visit("max_bytes", &max_bytes);
  }
};

/// One preview, camera frame. Points are whole millimetres (int16: +-32.7 m).
struct Preview {
  std::int64_t seq = 0;
  /// The decimated image, 3 bytes (RGB) a pixel, row-major: the frame's colour, or its depth as
  /// grey (near light, far dark) when the frame has no colour. `intrinsics` are its own.
  std::vector<std::uint8_t> rgb;
  CameraIntrinsics intrinsics;
  bool colour = false;  // rgb is the camera's colour (else the depth shaded)
  /// Foveated cloud points (x, y, z in mm) and each one's level (0: coarsest).
  std::vector<std::int16_t> points_mm;
  std::vector<std::uint8_t> levels;
  /// Each instance's model points at its pose (x, y, z in mm), and the instance they belong to
  /// (its index in the frame's detections).
  std::vector<std::int16_t> instance_points_mm;
  std::vector<std::uint8_t> instance_of_point;
  std::vector<Eigen::Vector3f> instance_centroids_m;  // per instance, camera frame
  /// The fovea's boxes: X_CB and each level's [min, max] in box coordinates (level 0 first).
  Eigen::Isometry3f camera_from_box = Eigen::Isometry3f::Identity();
  std::vector<Box> level_boxes;
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();
  float growth_m = 0;
  /// Where the frame's ground truth puts the target's centroid, when it has truth.
  bool has_truth = false;
  Eigen::Vector3f truth_centroid_m = Eigen::Vector3f::Zero();
};

/// A preview's points at most (the cloud's and the instances' together): what a viewer decodes.
constexpr int kPreviewMaxPoints = 20000;
/// A preview's instances at most (their points are tagged 128 + index in a byte).
constexpr int kPreviewMaxInstances = 127;

/// The models' points an instance is drawn with, model frame.
using PreviewModels = std::vector<const Cloud*>;

/// The preview of `scene` (organized, with `intrinsics`), foveated with `geometry`, with the
/// frame's instances drawn from `models` (indexed by Detection::model; a null or missing model
/// draws nothing). Points are evenly thinned to options.max_points and options.model_points.
Preview MakePreview(const Cloud& scene, const CameraIntrinsics& intrinsics,
                    const FoveaGeometry& geometry, const std::vector<Detection>& instances,
                    const PreviewModels& models, const PreviewOptions& options);

}  // namespace saccade
