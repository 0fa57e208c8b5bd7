// A synthetic Kinect: ray-casts primitive scenes into organized depth frames with a
// Kinect-like noise model, deterministically from a seed. Pure geometry, no I/O.
#pragma once

#include "core/mesh.h"
#include "core/types.h"

#include <array>

#include <cstdint>
#include <vector>

namespace saccade {

/// A solid made of boxes and spheres in its own frame (metres).
struct Shape {
  struct Part {
    enum class Kind { kBox, kSphere } kind = Kind::kBox;
    Eigen::Vector3f centre_m = Eigen::Vector3f::Zero();
    Eigen::Vector3f half_size_m = Eigen::Vector3f::Constant(0.05f);  // box half extents
    float radius_m = 0.05f;                                          // sphere radius

    static Part Box(const Eigen::Vector3f& centre, const Eigen::Vector3f& half_size) {
      Part p;
      p.centre_m = centre;
      p.half_size_m = half_size;
      return p;
    }
    static Part Sphere(const Eigen::Vector3f& centre, float radius) {
      Part p;
      p.kind = Kind::kSphere;
      p.centre_m = centre;
      p.radius_m = radius;
      return p;
    }
  };
  std::vector<Part> parts;
};

/// A distinctive, asymmetric target: four balls of different sizes on a slab, 14 x 14 x 10 cm;
/// its bottom face is at y = +0.05 in its own frame (y points down, as the camera's).
Shape TargetShape();

/// The shape as a triangle mesh in its own frame (boxes as 12 triangles, spheres as latitude
/// and longitude bands, `sphere_bands` of them), coloured `rgb`: the synthetic objects as a user
/// with their CAD would give them to `saccade model --mesh`.
Mesh ShapeMesh(const Shape& shape, int sphere_bands = 24,
               const std::array<std::uint8_t, 3>& rgb = {200, 60, 40});

struct SceneObject {
  Shape shape;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();  // X_CO: object O in camera C
  std::uint32_t label = 0;                                 // 0 = background
};

struct KinectNoise {
  bool enabled = true;
  double sigma_at_1m_m = 0.0015;    // depth noise grows with z²
  double disparity_step = 1.0 / 8;  // disparity quantization (pixels), Kinect v1: 1/8
  double baseline_m = 0.075;
  double min_range_m = 0.5, max_range_m = 4.0;
  double grazing_cos = 0.12;  // returns lost below this incidence cosine
  /// The IR projector sits baseline_m to the camera's right (+x in the camera frame), as on a
  /// Kinect: surfaces it cannot light, beside the left edges of nearer objects, have no return.
  bool projector_shadows = true;

  /// The keys of a scenario's `noise` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("enabled", &enabled);
    a->Visit("sigma_at_1m_m", &sigma_at_1m_m);
    a->Visit("disparity_step", &disparity_step);
    a->Visit("baseline_m", &baseline_m);
    a->Visit("min_range_m", &min_range_m);
    a->Visit("max_range_m", &max_range_m);
    a->Visit("grazing_cos", &grazing_cos);
    a->Visit("projector_shadows", &projector_shadows);
  }
};

struct RenderedFrame {
  Cloud cloud;                       // organized, NaN where there is no return
  std::vector<std::uint32_t> label;  // per pixel: the object label, 0 background / none
};

/// Renders the objects and a table plane (y = table_height_m in the camera frame, facing up).
RenderedFrame RenderScene(const std::vector<SceneObject>& objects, float table_height_m,
                          const CameraIntrinsics& intrinsics, const KinectNoise& noise,
                          std::uint32_t seed);

/// How many pixels of the objects labelled `label` RenderScene would return, with the same
/// geometry and sensor model but without drawing noise (noise moves depths; it never decides
/// which pixels return). Visits only the pixels onto which those objects can project.
std::size_t CountReturns(const std::vector<SceneObject>& objects, float table_height_m,
                         const CameraIntrinsics& intrinsics, const KinectNoise& noise,
                         std::uint32_t label);

/// The points of `label` in a frame, moved into the object's own frame by X_OC = X_CO^-1:
/// a model "cut from a capture", as a user would make one.
Cloud CutModel(const RenderedFrame& frame, std::uint32_t label, const Eigen::Isometry3f& X_CO);

/// A pose standing on the table: moved to (x, ., z), turned by `yaw_rad` about the table's
/// normal, with the object's bottom (at y = bottom_y_m in its own frame) on the table.
Eigen::Isometry3f PoseOnTable(float x_m, float z_m, float yaw_rad, float table_height_m,
                              float bottom_y_m = 0.05f);

}  // namespace saccade
