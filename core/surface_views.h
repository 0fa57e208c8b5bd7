// A whole surface (a model rendered from a mesh, or merged from captures around the object)
// as cameras around it would see it: which of its points each viewpoint sees. Describing such a
// model view by view gives descriptors a scene can match: a scene, too, shows one side, sampled
// on a camera's pixels (SHOT's local frames follow where the points are dense).
#pragma once

#include "core/camera.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace saccade {

/// `n` unit directions spread evenly over the sphere (a Fibonacci lattice), the same for a
/// given n on every run.
std::vector<Eigen::Vector3f> SphereDirections(int n);

/// A camera at `eye` looking at `target` (optical frame: z forward, y down where it can be),
/// camera-to-world.
Eigen::Matrix4f LookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target);

/// How far from the centre of an object within `radius_m` of it a camera with `intrinsics`
/// stands to see all of it from any side (within 90% of the image's shorter side), and at least
/// `at_least_m`.
float ViewDistance(float radius_m, const CameraIntrinsics& intrinsics, float at_least_m);

/// What a camera sees of a whole surface: its pixels' points (camera frame), each with the
/// index of the surface point whose disc it lies on.
struct SurfaceView {
  Cloud points;
  std::vector<int> source;
};

/// Renders `surface` as seen by a camera with `intrinsics` at `camera_to_surface`: every point
/// is a disc of `disc_radius_m` on the plane its normal gives (so the view is sampled on the
/// camera's pixel grid, as a capture is, with depths on the surface between the points), the
/// nearest disc along each pixel's ray wins, and with `noise_at_1m_m` > 0 each depth is moved by
/// a normal draw of that deviation times z squared (a Kinect's noise), from `seed`. `normals`
/// may point either way; points or normals that are not finite are left out.
SurfaceView RenderSurface(const Cloud& surface, const std::vector<Eigen::Vector3f>& normals,
                          const CameraIntrinsics& intrinsics,
                          const Eigen::Matrix4f& camera_to_surface, float disc_radius_m,
                          float noise_at_1m_m = 0, unsigned seed = 0);

}  // namespace saccade
