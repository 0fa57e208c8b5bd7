// The foveated point cloud of Gomes et al. 2013, §3: m+1 nested boxes around a fixation point
// (the fovea), each level downsampled to its own density, levels disjoint (Algorithm 1).
#pragma once

#include "core/schema.h"
#include "core/types.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

/// Parameters of the foveated model. All lengths in metres, in the camera frame. The defaults
/// are Saccade's (measured in docs/BENCHMARKS.md); the paper's Table 2 values are noted where
/// they differ and are shipped as configs/paper.yaml.
struct FoveaOptions {
  int finest_level = 2;  // m: number of levels minus one (m >= 1); paper: 3
  /// When true the outer box is the axis-aligned bounding box of each scene's finite points and
  /// outer_size_m / outer_min_corner_m / outer_orientation are ignored.
  bool outer_box_from_scene = true;
  Eigen::Vector3f outer_size_m{3.0f, 3.0f, 3.0f};           // S_0
  Eigen::Vector3f outer_min_corner_m{-2.9f, -1.9f, -1.3f};  // Δ: outer box origin, camera frame
  /// Orientation of the outer box axes in the camera frame (R_CB). Identity: camera-aligned.
  Eigen::Quaternionf outer_orientation = Eigen::Quaternionf::Identity();
  Eigen::Vector3f inner_size_m{0.25f, 0.25f, 0.25f};  // S_m: the fovea's own box; paper: 0.5
  Eigen::Vector3f growth_m{0.0f, 0.0f, 0.0f};         // G: every level grows by G on each side
  float outer_density_m = 0.03f;  // d_0: voxel leaf of the coarsest level (0 keeps every point)
  float inner_density_m = 0.0f;   // d_m: voxel leaf of the fovea level (0 keeps every point)
  float outer_keypoint_radius_m = 0.08f;   // r_0: keypoint sampling radius of level 0
  float inner_keypoint_radius_m = 0.012f;  // r_m: keypoint sampling radius of level m; paper: 0.02

  /// Returns true when usable; otherwise false with `error` naming the offending field.
  bool IsValid(std::string* error) const;
  bool operator==(const FoveaOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const FoveaOptions& o) const { return !(*this == o); }
  /// The keys of the `fovea` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("finest_level", &finest_level);
    a->Visit("outer_box_from_scene", &outer_box_from_scene);
    a->Visit("outer_size_m", &outer_size_m);
    a->Visit("outer_min_corner_m", &outer_min_corner_m);
    a->Visit("outer_orientation", &outer_orientation);
    a->Visit("inner_size_m", &inner_size_m);
    a->Visit("growth_m", &growth_m);
    a->Visit("outer_density_m", &outer_density_m);
    a->Visit("inner_density_m", &inner_density_m);
    a->Visit("outer_keypoint_radius_m", &outer_keypoint_radius_m);
    a->Visit("inner_keypoint_radius_m", &inner_keypoint_radius_m);
  }
};

/// d_k = d_0 + k (d_m - d_0) / m, the leaf of level k.
float LevelDensity(const FoveaOptions& options, int k);
/// r_k = r_0 + k (r_m - r_0) / m, the keypoint radius of level k (paper §4.2).
float LevelKeypointRadius(const FoveaOptions& options, int k);

/// Eq. 1: δ_k, the min corner of box k in outer-box coordinates, for the fovea F relative to
/// the outer box centre. Written so that δ_0 = 0 and δ_m + S_m/2 = F' = F + S_0/2, the two
/// conditions the paper states (its printed form drops the parentheses around k).
Eigen::Vector3f LevelDisplacement(int k, int m, const Eigen::Vector3f& outer_size,
                                  const Eigen::Vector3f& inner_size, const Eigen::Vector3f& fovea);
/// Eq. 2: S_k = (k S_m - k S_0 + m S_0) / m.
Eigen::Vector3f LevelSize(int k, int m, const Eigen::Vector3f& outer_size,
                          const Eigen::Vector3f& inner_size);

/// Where the boxes of one foveation lie.
struct FoveaGeometry {
  Eigen::Isometry3f box_from_camera = Eigen::Isometry3f::Identity();  // X_BC
  Eigen::Vector3f outer_size_m = Eigen::Vector3f::Zero();             // S_0
  Eigen::Vector3f fovea_in_box_m = Eigen::Vector3f::Zero();           // F' (box coordinates)
  /// Box k in box coordinates: [max(δ_k - G, 0), min(δ_k + S_k + G, S_0)].
  std::vector<Box> levels;

  /// The outer box itself, [0, S_0], in box coordinates.
  Box OuterBox() const { return Box{Eigen::Vector3f::Zero(), outer_size_m}; }
};

/// The axis-aligned bounding box of the finite points, camera frame; nullopt when none is finite.
std::optional<Box> BoundingBox(const Cloud& cloud);

/// Places the boxes for a fovea given in the camera frame. `scene_bounds` is used when
/// options.outer_box_from_scene (it is grown to at least S_m on every axis).
/// Precondition: options.IsValid().
FoveaGeometry ComputeFoveaGeometry(const FoveaOptions& options, const Box& scene_bounds,
                                   const Eigen::Vector3f& fovea_camera);

/// A foveated cloud: the kept points of every level, joined and ordered by level.
struct FoveatedCloud {
  FoveaGeometry geometry;
  Cloud cloud;                      // joined cloud, level 0 first
  std::vector<int> source_index;    // per point: its index in the input cloud
  std::vector<std::uint8_t> level;  // per point: its level k
  std::vector<std::size_t>
      level_begin;  // m+2 offsets: level k is [level_begin[k], level_begin[k+1])

  int NumLevels() const { return static_cast<int>(level_begin.size()) - 1; }
  std::size_t LevelPointCount(int k) const { return level_begin[k + 1] - level_begin[k]; }
  /// A copy of level k as its own cloud.
  Cloud LevelCloud(int k) const;
};

/// Which level region each input point falls in (Algorithm 1's "inside box k and not inside box
/// k+1"), or -1 when it is not finite or outside the outer box.
int LevelOf(const FoveaGeometry& geometry, const Eigen::Vector3f& point_camera);

/// Algorithm 1: classifies every input point into its level, downsamples each level with its
/// d_k (the kept point of a voxel is the input point nearest the voxel centre, so coordinates
/// are never averaged across levels), and joins the levels. Precondition: options.IsValid().
FoveatedCloud Foveate(const Cloud& scene, const FoveaOptions& options,
                      const FoveaGeometry& geometry);

/// The kept input points of each level (Algorithm 1 after downsampling), as indices into
/// `scene`, for the levels k >= first_level only (lower levels come back empty: a caller that
/// will not use the periphery need not pay for it). With `intrinsics` and an organized scene,
/// only the pixels onto which box first_level projects are visited.
std::vector<std::vector<int>> FoveateIndices(const Cloud& scene, const FoveaOptions& options,
                                             const FoveaGeometry& geometry, int first_level = 0,
                                             const CameraIntrinsics* intrinsics = nullptr);

/// Uniform sampling: of the candidate points, keeps per cubic voxel of edge `leaf_m` the one
/// nearest the voxel centre; leaf_m <= 0 keeps every candidate. Output in first-seen order.
std::vector<int> VoxelRepresentatives(const Cloud& cloud, const std::vector<int>& candidates,
                                      float leaf_m);

}  // namespace saccade
