// Object recognition by correspondence grouping (paper §4): SHOT descriptors with local
// reference frames, nearest-neighbour matching in descriptor space, 3D Hough voting.
// The model is described once and reused for every scene; scenes may be foveated or plain.
#pragma once

#include "core/features.h"
#include "core/foveation.h"
#include "core/grouping.h"
#include "core/model.h"
#include "core/parallel.h"
#include "core/recognition_options.h"
#include "core/types.h"
#include "core/verification.h"

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace saccade {
/// What a recognition run did, for logs and benchmarks.
struct RecognitionStats {
  std::vector<std::size_t> level_points;     // kept points per level (one level when plain)
  std::vector<std::size_t> level_keypoints;  // keypoints per level
  std::size_t described = 0;                 // keypoints with a valid descriptor
  std::size_t correspondences = 0;           // matches below d²_max
  std::size_t hypotheses = 0;                // instances from grouping, before verification
  std::size_t table_keypoints = 0;  // keypoints on the table, not described (in level_keypoints)
  std::size_t budgeted_out = 0;  // keypoints left out by max_scene_keypoints (in level_keypoints)
  int search_windows = 1;        // windows the budget cut the keypoints into
  /// Milliseconds per stage: foveate, normals, keypoints, describe, match, group, verify, total.
  std::vector<std::pair<std::string, double>> stage_ms;
  std::size_t TotalPoints() const;
  std::size_t TotalKeypoints() const;
};

struct RecognitionResult {
  /// Verified: best first (then those a model of views kept by one view, VerifyByViews, most
  /// confident first); unverified: by votes, most first.
  std::vector<Detection> instances;
  /// What grouping proposed before verification (by votes, most first; the same as `instances`
  /// when verification is off): for evaluations that ask where a miss was lost.
  std::vector<Detection> hypotheses;
  std::vector<Verdict> verdicts;  // verification's, one per hypothesis; empty when off
  /// Every descriptor match below d²_max as (model point index, scene point index).
  std::vector<std::pair<int, int>> correspondences;
  RecognitionStats stats;
  std::optional<FoveaGeometry> fovea;  // set when foveated
};

/// Where to look. Plain: no foveation, one keypoint radius r_ks over the whole scene.
struct SceneQuery {
  bool foveated = true;
  Eigen::Vector3f fovea_m = Eigen::Vector3f::Zero();  // camera frame; used when foveated
  FoveaOptions fovea;
  /// Intrinsics of an organized scene; estimated from the cloud when absent.
  std::optional<CameraIntrinsics> intrinsics;
  /// Which window of the keypoints a budgeted search describes (max_scene_keypoints): even
  /// phases the nearest the fovea, odd ones the others in turn. The daemon passes the frames
  /// searched since the target was lost.
  int search_phase = 0;
};

/// Recognizes the model in the scene. Expected outcomes (no finite point, nothing found) are
/// values: an empty instance list, with `error` set only when the scene could not be processed.
/// Preconditions: options.IsValid(), query.fovea.IsValid().
RecognitionResult Recognize(const ModelDescription& model, const Cloud& scene,
                            const SceneQuery& query, const RecognitionOptions& options,
                            const ParallelFor& parallel_for = SerialFor,
                            std::string* error = nullptr);

/// Recognize's stages, for a search that describes a scene once for several models
/// (core/library.h). Recognize(model) is DescribeScene, matching against the model's index,
/// then GroupAndVerify.
struct SceneDescription {
  Descriptors descriptors;                     // keypoints index the scene
  std::optional<CameraIntrinsics> intrinsics;  // set when the scene is organized
  std::optional<FoveaGeometry> fovea;          // set when foveated
  RecognitionStats stats;                      // foveate, keypoints, normals, describe
};
/// Keypoints and descriptors of the scene where the query looks, with `options`' scene radii
/// (already fitted to the model). nullopt with `error` when the scene has no finite point.
/// Descriptions of one frame at several radii may share `shared_normals`: each point's normal
/// is then computed once.
std::optional<SceneDescription> DescribeScene(const Cloud& scene, const SceneQuery& query,
                                              const RecognitionOptions& options,
                                              const ParallelFor& parallel_for, std::string* error,
                                              SceneNormals* shared_normals = nullptr);
/// Hough and consensus grouping of `correspondences` (model descriptor, scene descriptor), then
/// verification: fills result's instances, hypotheses, verdicts, correspondences and stats.
void GroupAndVerify(const ModelDescription& model, const Cloud& scene,
                    const SceneDescription& described,
                    const std::vector<std::pair<int, int>>& correspondences,
                    const RecognitionOptions& options, const ParallelFor& parallel_for,
                    RecognitionResult* result);

/// Translation error at a point (the model centroid) and rotation angle error, between poses.
struct PoseError {
  double translation_m = 0;
  double rotation_deg = 0;
};
PoseError ComparePoses(const Eigen::Matrix4f& estimate, const Eigen::Matrix4f& truth,
                       const Eigen::Vector3f& model_point);

}  // namespace saccade
