// Hypothesis verification: each instance from grouping is refined by ICP against the scene near
// it and kept only when the model, so placed, explains what the sensor saw: enough of its points
// lie on the scene's surface, few would stand in front of surface the sensor saw through them,
// and (optionally) their colours agree.
#pragma once

#include "core/parallel.h"
#include "core/schema.h"
#include "core/types.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

struct VerificationOptions {
  bool enabled = true;
  int max_candidates = 8;            // instances verified, most votes first; the rest are dropped
  int model_points = 600;            // model points used (an even subset)
  int icp_points = 200;              // of those, about this many are aligned by ICP
  int icp_iterations = 12;           // ICP steps (point to point) per candidate
  float icp_max_distance_m = 0.03f;  // pairs farther apart are ignored by ICP's first step
  float inlier_distance_m = 0.008f;  // a model point this near the scene lies on its surface
  /// Kept when inliers / (inliers + points in front of seen surface) reaches this.
  float min_fitness = 0.6f;
  /// ...and inliers / model points used reaches this (the share of the model found).
  float min_coverage = 0.15f;
  /// ...and the model points on the surface are not flatter than this share of the model's
  /// thickness: a model laid into the table fits its flat parts to the table and nothing else.
  /// (0.35 lost a flat box seen from another side, whose visible part is thin at best.)
  float min_depth_ratio = 0.3f;
  /// Colour check (when both clouds have colour): the rg-chromaticity histograms of the model
  /// points on the scene's surface and of the scene points they lie on must intersect by at
  /// least this much. 0: no hard check; the agreement is still measured and weighs in the
  /// confidence (the default: a hard check at 0.7 rejected about 50 true instances of the
  /// cross-capture benchmark, docs/RESULTS.md).
  float min_colour_agreement = 0.0f;
  /// Measure colour when both clouds have it; off: verify as if neither had (what a live
  /// depth-only frame gives).
  bool use_colour = true;
  /// Kept when its confidence (InstanceConfidence) reaches this.
  float min_confidence = 0.5f;
  /// A model of several captured views: a pose the whole model fails is verified again against
  /// the view most of its votes came from (a view its alignment misplaced hides a right pose),
  /// and kept when that confidence reaches this (and min_confidence). A second try is a second
  /// chance for a wrong pose too (docs/RESULTS.md, "A view verified alone"). 1: no second try.
  float min_view_confidence = 0.8f;
  /// A camera-facing model point this far or less behind the seen surface is sunk into it.
  float max_sink_m = 0.05f;
  /// Kept when at most this share of the places just outside the instance's outline (as the
  /// pose projects it into an organized frame) continue its surface at its depth: an object has
  /// an outline where the sensor sees past it or sees nothing, a patch of a wall, a board or a
  /// larger object has none. 1: not checked. (0.7, 0.75 and 1 on the cross-capture benchmark:
  /// docs/RESULTS.md, "Outlines".)
  float max_continued = 0.7f;

  bool IsValid(std::string* error) const;
  bool operator==(const VerificationOptions& o) const { return SameFields(*this, o); }
  bool operator!=(const VerificationOptions& o) const { return !(*this == o); }
  /// The keys, as they appear in the recognition section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("verify", &enabled);
    a->Visit("verify_candidates", &max_candidates);
    a->Visit("verify_model_points", &model_points);
    a->Visit("verify_icp_points", &icp_points);
    a->Visit("verify_icp_iterations", &icp_iterations);
    a->Visit("verify_icp_max_distance_m", &icp_max_distance_m);
    a->Visit("verify_inlier_distance_m", &inlier_distance_m);
    a->Visit("verify_min_fitness", &min_fitness);
    a->Visit("verify_min_coverage", &min_coverage);
    a->Visit("verify_min_depth_ratio", &min_depth_ratio);
    a->Visit("verify_min_colour_agreement", &min_colour_agreement);
    a->Visit("verify_min_confidence", &min_confidence);
    a->Visit("verify_min_view_confidence", &min_view_confidence);
    a->Visit("verify_colour", &use_colour);
    a->Visit("verify_max_sink_m", &max_sink_m);
    a->Visit("verify_max_continued", &max_continued);
  }
};

/// What verification needs of the model, prepared once: an even subset of its points with their
/// normals (model frame; normals face the sensor that captured the model), and its bounds.
struct VerificationModel {
  Cloud points;
  std::vector<Eigen::Vector3f> normals;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();  // of the bounding box
  float radius_m = 0;                                // half the bounding box's diagonal
  bool coloured = false;
  float thickness_m = 0;  // spread along the least-spread direction: 0 for a planar model
  /// The whole surface (a mesh rendered from all around), its normals facing out: only the
  /// points a pose turns towards the camera are aligned and counted, and the share found is of
  /// those (a captured model is one view: every point counts).
  bool whole_surface = false;
  /// ...and a point counts only where its normal is at least this cosine from edge-on to the
  /// line of sight: a depth sensor returns little of a face it sees almost edge-on. Set for a
  /// rendered mesh, whose normals are exact; 0 for captured views, whose estimated normals a cut
  /// would misjudge (docs/RESULTS.md, "Symmetric models").
  float min_facing = 0;
  /// The median distance between neighbouring `points`: how finely they cover the model.
  float spacing_m = 0;
};

/// At most `max_points` of the model's finite points; `normals` are per model point (NaN where
/// unknown).
VerificationModel MakeVerificationModel(const Cloud& model,
                                        const std::vector<Eigen::Vector3f>& normals,
                                        int max_points);

/// True when the points carry colour: more than one colour among them (a cloud saved without
/// colour reads as all black, and some files fill the field with one constant).
bool HasColour(const Cloud& cloud);

/// The Pearson correlation of brightness between `model`'s points `model_points` and `scene`'s
/// points `scene_points` (pairs, index for index), in [-1, 1]; -1 when fewer than 20 pairs or
/// either side is too plain (grey-level spread under 8) for a pattern to tell anything.
float TextureAgreement(const Cloud& model, const std::vector<int>& model_points, const Cloud& scene,
                       const std::vector<int>& scene_points);

/// How likely a verified instance is the object, in [0, 1]: a logistic model of its votes,
/// fitness, coverage, colour agreement (-1: not measured, a model without colour is used) and
/// `relative_fit` (its fitness x coverage over the frame's best candidate's), calibrated on the
/// cross-capture benchmark (docs/RESULTS.md).
float InstanceConfidence(const Detection& d, float relative_fit);

/// Why verification kept or dropped a candidate, in the order the checks run.
enum class Verdict {
  kKept,
  kNotChecked,     // beyond max_candidates
  kNoFit,          // fitness or coverage too low
  kFlat,           // the points on the surface are flatter than the model
  kColour,         // the colours of the explained scene points disagree
  kNoOutline,      // the scene's surface continues past its outline (max_continued)
  kUnconfident,    // its confidence is below min_confidence
  kTakenByBetter,  // a better instance already explains its points or overlaps it
  kFewVotes,       // not verified: its votes do not stand out of its model's matches
};
const char* VerdictName(Verdict v);
/// True when one of verification's checks refused the candidate (no fit, flat, colour, no outline,
/// unconfident): not when it was kept, left unchecked, had too few votes, or a better one took it.
bool FailedACheck(Verdict v);

/// The share of the places just outside the outline of `points` (camera frame, projected with
/// `k` into the organized `scene`, spaced about `spacing_m` apart) where the scene continues
/// their surface: within `tolerance_m` of the depth of the nearest of them. A place where the
/// sensor sees past them or sees nothing is an outline; one in front of them (an occluder) is
/// not counted. -1 when there is nothing to count.
float ContinuedShare(const std::vector<Eigen::Vector3f>& points, float spacing_m,
                     const Cloud& scene, const CameraIntrinsics& k, float tolerance_m);

/// Refines and filters `instances` (poses of the model in `scene`), returning the kept ones,
/// best first, each with its fitness, coverage and colour agreement set. With intrinsics (an
/// organized scene) model points that face the camera and would stand in front of the seen
/// surface, or just behind it (sunk into a surface rather than hidden by something), count
/// against an instance; without them only distances to the scene count. `vote_point` (model
/// frame) is where centroid_m is. `verdicts`, when given, gets one verdict per input instance.
std::vector<Detection> VerifyInstances(const VerificationModel& model,
                                       const Eigen::Vector3f& vote_point, const Cloud& scene,
                                       const std::optional<CameraIntrinsics>& intrinsics,
                                       std::vector<Detection> instances,
                                       const VerificationOptions& options,
                                       const ParallelFor& parallel_for = SerialFor,
                                       std::vector<Verdict>* verdicts = nullptr);

}  // namespace saccade
