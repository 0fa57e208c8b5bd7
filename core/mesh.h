// A triangle mesh (a CAD part, a scan, a Blender export) made into a model Saccade can search
// for: the mesh rendered, z-buffered, from viewpoints all around it by a camera with the
// sensor's intrinsics, so the model holds the whole surface at the density a capture would give,
// and what each viewpoint saw.
#pragma once

#include "core/camera.h"
#include "core/types.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace saccade {

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;      // metres, the model's frame
  std::vector<std::array<int, 3>> triangles;  // vertex indices
  /// A colour per vertex (vertex_colours.size() == vertices.size()) or per triangle
  /// (face_colours.size() == triangles.size()), or neither (rendered grey).
  std::vector<std::array<std::uint8_t, 3>> vertex_colours, face_colours;
};

/// Checks that every index is in range and some triangle has an area; one line naming what is
/// wrong otherwise.
bool IsValidMesh(const Mesh& mesh, std::string* error);

struct MeshViewOptions {
  int views = 42;               // viewpoints, evenly spread over a sphere around the mesh
  float distance_m = 0.8f;      // from the mesh's centre to each viewpoint
  float spacing_m = 0.002f;     // the merged surface keeps one point per cube of this edge
  CameraIntrinsics intrinsics;  // the rendering camera's (the sensor's)
  bool IsValid(std::string* error) const;
};

/// What the rendering gave: the whole visible surface in the mesh's frame, with normals facing
/// out of it (towards the viewpoints that saw each point), and each view's share of it.
struct MeshModel {
  Cloud points;
  std::vector<Eigen::Vector3f> normals;
  std::vector<Eigen::Vector3f> viewpoints;  // each view's camera centre, mesh frame
  std::vector<int> points_per_view;         // pixels each view saw of the mesh
};

/// Renders `mesh` from `options.views` viewpoints and merges what they saw; the cloud's sensor
/// origin is the mesh's centre (a whole surface, seen from no one place). The mesh must be
/// valid (IsValidMesh).
MeshModel RenderMeshModel(const Mesh& mesh, const MeshViewOptions& options);

/// One view: the depth (metres, NaN where the mesh is not seen) and the triangle index (-1)
/// at each pixel of a camera at `pose` (camera-to-mesh, camera looking down its +z axis).
struct MeshDepth {
  int width = 0, height = 0;
  std::vector<float> depth;
  std::vector<int> triangle;
};
MeshDepth RenderMeshDepth(const Mesh& mesh, const CameraIntrinsics& intrinsics,
                          const Eigen::Matrix4f& camera_to_mesh);

}  // namespace saccade
