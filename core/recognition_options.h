// The options of correspondence grouping (paper Table 1, and Saccade's defaults beside them).
#pragma once

#include "core/schema.h"
#include "core/verification.h"

#include <string>
#include <vector>

namespace saccade {

/// Correspondence-grouping parameters, in metres. "scene" values apply to the scene cloud,
/// "model" values to the model cloud. The defaults are Saccade's (docs/RESULTS.md): radii fitted
/// to each model, wide supports sampled, a quick descriptor match. The radius fields hold the
/// paper's Table 1 values and are used as given only with radii_from_model off
/// (configs/paper.yaml, Paper()).
struct RecognitionOptions {
  int scene_normal_neighbors = 10;        // k_ns
  float scene_keypoint_radius_m = 0.03f;  // r_ks (plain recognition only)
  float scene_shot_radius_m = 0.02f;      // r_ss
  float scene_lrf_radius_m = 0.015f;      // r_ls
  int model_normal_neighbors = 10;        // k_nm
  float model_keypoint_radius_m = 0.01f;  // r_km
  // A whole-surface model (from a mesh) is described as a Kinect would capture it from this many
  // viewpoints around it, this far from its centre, with this depth noise at 1 m (x z²).
  int model_views = 20;
  float model_view_distance_m = 0.9f;
  float model_view_noise_m = 0.0015f;
  // ... and its keypoints whose SHOT support lies within this share of the SHOT radius of a
  // plane (RMS) are left out: a flat patch matches every table and wall.
  float model_min_relief = 0.1f;
  float model_shot_radius_m = 0.02f;          // r_sm
  float model_lrf_radius_m = 0.015f;          // r_lm
  float max_descriptor_sqr_distance = 0.25f;  // d²_max: accept a match below this
  float hough_bin_m = 0.01f;                  // L_h
  int hough_threshold = 5;                    // V_h: minimum votes of an instance
  /// A correspondence stays in an instance when the instance's pose maps its model keypoint
  /// within this distance of its scene keypoint.
  float pose_inlier_threshold_m = 0.02f;
  /// Levels coarser than this (by d_k) are not described: a SHOT support of a few points is
  /// noise (PERFORMANCE.md §2). Their points still count as surface for finer levels.
  float max_described_density_m = 0.01f;
  /// On an organized scene, SHOT and LRF supports whose pixel window reaches farther than this
  /// from the keypoint (wide radii, near the camera) are sampled every few pixels down to about
  /// this window's point count: the histogram's shape is kept at a fraction of the cost. 0: use
  /// every pixel.
  int max_support_half_window_px = 8;
  /// The search budget of a frame (issue 16): at most this many scene keypoints are described.
  /// When a grown fovea has more, they are ordered by distance from the fovea's centre and the
  /// frame describes one window of that order, the query's search_phase choosing which: every
  /// other frame the nearest, the frames between the others in turn, outward (windows overlap
  /// by half, so an object on a window's edge is whole in the next). 0: no budget (one frame
  /// searches everything: the evaluation's protocols). saccaded sets 1200 (daemon/settings.h).
  int max_scene_keypoints = 0;
  /// Correspondences vote for where the model's centroid lies (paper Algorithm 5). With this
  /// set they vote for the model frame's origin instead: right for a model whose frame is
  /// centred on the object (a ball cut around its centre), where the centroid of the seen cap
  /// is off-centre and every local frame's free spin about the normal scatters its votes.
  bool vote_for_model_origin = false;
  /// Matching: a hierarchical k-means tree over the model descriptors (branching factor) and
  /// the descriptors compared per query (more: closer to exact, slower).
  int match_branching = 8;
  int match_checks = 16;
  unsigned match_seed = 42;
  /// A second hypothesis generator beside Hough voting: each match's two local frames give a
  /// whole pose, the poses most matches agree with (within pose_inlier_threshold_m) are refit
  /// on them and proposed. It finds an object whose few true matches scatter over Hough cells.
  bool consensus_grouping = true;
  int consensus_min_votes = 4;       // matches that must agree on a proposed pose
  int consensus_max_hypotheses = 8;  // proposals at most, most agreed first
  /// A hypothesis is verified only when its votes reach this x the square root of the matches
  /// its model won in the frame: a plain or flat model wins thousands of a frame's descriptors
  /// (table, walls) and some agree by chance; votes that stand out of a model's own matches as
  /// a count stands out of its noise do not. 0: no bar beyond hough_threshold. (Chosen on the
  /// library benchmark, docs/RESULTS.md "Votes that stand out".)
  float min_vote_significance = 0.4f;
  /// Scene keypoints within this distance of the frame's table (its largest plane, found as
  /// the candidates find it; an organized frame only) are not described: on a whole frame most
  /// keypoints lie on the table, whose flat patches match every flat face of a model. Its points
  /// still support the descriptors around them and verification. 0: the table is described
  /// (Paper()). 1.5 cm is the candidates' table distance (CandidateOptions::plane_distance_m),
  /// not tuned here (docs/RESULTS.md "The table is not described").
  float table_keypoint_distance_m = 0.015f;
  /// Hypothesis verification after grouping (ICP, surface and free-space checks, colour).
  VerificationOptions verify;
  /// Replace the radii above (keypoints, SHOT, LRF, Hough bin, pose inliers) by ones fitted to
  /// the model's size and point spacing (FitRadii), so a new object needs no hand tuning.
  bool radii_from_model = true;
  /// Several models searched at once (core/library.h): each model's fitted SHOT radius is
  /// rounded to the nearest 3 cm x ratio^k, so that models of similar size share one
  /// description of each frame and one descriptor index. 1: as fitted (one description per
  /// model). A single model is never rounded.
  float library_radius_ratio = 1.25f;

  bool IsValid(std::string* error) const;
  bool operator==(const RecognitionOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const RecognitionOptions& o) const { return !(*this == o); }
  /// The keys of the `recognition` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("scene_normal_neighbors", &scene_normal_neighbors);
    a->Visit("scene_keypoint_radius_m", &scene_keypoint_radius_m);
    a->Visit("scene_shot_radius_m", &scene_shot_radius_m);
    a->Visit("scene_lrf_radius_m", &scene_lrf_radius_m);
    a->Visit("model_normal_neighbors", &model_normal_neighbors);
    a->Visit("model_keypoint_radius_m", &model_keypoint_radius_m);
    a->Visit("model_views", &model_views);
    a->Visit("model_view_distance_m", &model_view_distance_m);
    a->Visit("model_view_noise_m", &model_view_noise_m);
    a->Visit("model_min_relief", &model_min_relief);
    a->Visit("model_shot_radius_m", &model_shot_radius_m);
    a->Visit("model_lrf_radius_m", &model_lrf_radius_m);
    a->Visit("max_descriptor_sqr_distance", &max_descriptor_sqr_distance);
    a->Visit("hough_bin_m", &hough_bin_m);
    a->Visit("hough_threshold", &hough_threshold);
    a->Visit("pose_inlier_threshold_m", &pose_inlier_threshold_m);
    a->Visit("max_described_density_m", &max_described_density_m);
    a->Visit("max_support_half_window_px", &max_support_half_window_px);
    a->Visit("max_scene_keypoints", &max_scene_keypoints);
    a->Visit("vote_for_model_origin", &vote_for_model_origin);
    a->Visit("match_branching", &match_branching);
    a->Visit("match_checks", &match_checks);
    a->Visit("match_seed", &match_seed);
    a->Visit("radii_from_model", &radii_from_model);
    a->Visit("library_radius_ratio", &library_radius_ratio);
    a->Visit("consensus_grouping", &consensus_grouping);
    a->Visit("consensus_min_votes", &consensus_min_votes);
    a->Visit("min_vote_significance", &min_vote_significance);
    a->Visit("table_keypoint_distance_m", &table_keypoint_distance_m);
    a->Visit("consensus_max_hypotheses", &consensus_max_hypotheses);
    verify.Serialize(a);
  }
  /// The keys FitRadii replaces while radii_from_model is set: a file that sets them is told
  /// they are ignored.
  std::vector<std::string> IgnoredKeys() const;

  /// The paper's Table 1 as given: hand-set radii, every support pixel, and the slower, nearer
  /// exact match Saccade used before fitted radii.
  static RecognitionOptions Paper();
  /// Table 1's values were tuned for a model cut from the very frame it is searched in. A
  /// model from another capture needs wider supports (repeatable local frames from another
  /// viewpoint) and a coarser Hough grid (the residual frame error); see docs/BENCHMARKS.md.
  /// Hand-set radii, from Paper().
  static RecognitionOptions CrossCapture();
};

}  // namespace saccade
