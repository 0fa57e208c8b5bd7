// Where in the whole frame the model may be, before any descriptor is computed: the table plane
// is removed from a coarse view of the frame, and what stands above it is scored in model-sized
// windows by how well the amount of it matches what the model would cover at that depth, by
// whether it is as thick as the model (a patch of a wall or a board is flat, a solid object seen
// at a corner is not), and by how much of it has the model's colours (histogram
// back-projection, Swain and Ballard 1991).
// The attention loop sends the fovea to the best candidates first; recognition and verification
// at each decide. Pure: an organized cloud in, ranked points out.
#pragma once

#include "core/camera.h"
#include "core/colour.h"
#include "core/schema.h"
#include "core/types.h"
#include "core/verification.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace saccade {

class ModelDescription;  // core/model.h

struct CandidateOptions {
  int stride_px = 4;                // the coarse view: every stride-th pixel of every stride-th row
  float z_max_m = 3.0f;             // points farther than this are left out
  float plane_distance_m = 0.015f;  // a point this near the table plane is the table
  /// The largest plane is the table when it holds at least this share of the coarse points;
  /// otherwise nothing is removed.
  float min_plane_fraction = 0.1f;
  int plane_iterations = 200;  // RANSAC hypotheses
  int max_candidates = 12;
  /// Colour's share of a candidate's score (0: geometry alone; used only when the model and the
  /// frame both have colour).
  float colour_weight = 0.75f;
  /// Thickness's share of a candidate's score: a window thinner than the model (its points'
  /// spread across their flattest direction) scores less, in proportion (0: not looked at).
  float shape_weight = 0.5f;
  /// Standing apart's share of a candidate's score: a window whose surroundings (the shell just
  /// outside it) hold as many points as it does, a patch of something larger, scores less, in
  /// proportion (0: not looked at). A model whose sides differ in area (a rendered mesh) gives
  /// it more: 1 - (1 - apart_weight) x its least side's area over its largest's.
  float apart_weight = 0.0f;
  std::uint32_t seed = 1;  // RANSAC's: the same frame gives the same candidates

  bool IsValid(std::string* error) const;
  bool operator==(const CandidateOptions& o) const { return SameFields(*this, o); }
  /// The keys of the `candidates` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("stride_px", &stride_px);
    a->Visit("z_max_m", &z_max_m);
    a->Visit("plane_distance_m", &plane_distance_m);
    a->Visit("min_plane_fraction", &min_plane_fraction);
    a->Visit("plane_iterations", &plane_iterations);
    a->Visit("max_candidates", &max_candidates);
    a->Visit("colour_weight", &colour_weight);
    a->Visit("shape_weight", &shape_weight);
    a->Visit("apart_weight", &apart_weight);
  }
};

/// What the proposer needs of a model, measured once from its cloud.
struct ModelSignature {
  float radius_m = 0;  // half the bounding box's diagonal
  /// The area the sensor sees of it (its points times the square of their median spacing):
  /// what a window at depth z should hold, in pixels, is area * (f / z)^2.
  float seen_area_m2 = 0;
  /// The range of areas a window may hold and still be the model: a whole surface looks larger
  /// from some sides than from others (a cube face-on against corner-on). Both equal
  /// seen_area_m2 for a model captured from one side.
  float seen_area_min_m2 = 0, seen_area_max_m2 = 0;
  /// The areas are a whole surface's silhouettes, the object entire; a captured model's are
  /// what its capture kept of it.
  bool silhouettes = false;
  ColourHistogram colour{};  // normalized; meaningful when `coloured`
  bool coloured = false;
  /// How thick the model is as the sensor sees it: the root of its points' least covariance
  /// eigenvalue (0 for one flat face; about a third of the edge for a box seen at a corner).
  float thickness_m = 0;
};

/// The signature of a model cloud whose median point spacing is `spacing_m` (ModelScale). A
/// rendered mesh (`surface` given, whole_surface, its exact normals cut at min_facing > 0) is
/// looked at from 64 sides: a window may hold the area of any side's silhouette, and is as thick
/// as the median side's facing points. Captures of several sides are seen half at a time: half
/// their area and half their thickness (silhouettes lost cases on them, docs/RESULTS.md).
ModelSignature SignModel(const Cloud& model, float spacing_m,
                         const VerificationModel* surface = nullptr);
/// The signature of a described model: its cloud, its spacing and its verification surface.
ModelSignature SignModel(const ModelDescription& model);

/// One place the model may be, camera frame.
struct Candidate {
  Eigen::Vector3f centre_m = Eigen::Vector3f::Zero();  // the window's weighted centroid
  /// In [0, 1]: fill x ((1 - s) + s x shape) x ((1 - w) + w x colour) x ((1 - a) + a x apart),
  /// s = shape_weight, w = colour_weight and a apart's share (CandidateOptions::apart_weight).
  float score = 0;
  /// The window's points against what the model would cover there: the smaller of the two
  /// ratios, 1 when they are equal.
  float fill = 0;
  /// The window's thickness against the model's (ModelSignature::thickness_m), at most 1.
  float shape = 1;
  float colour = 1;  // the share of its points whose colour the model has (1 without colour)
  /// 1 - the points of the shell just outside the window over the window's, at least 0.
  float apart = 1;
  int points = 0;  // coarse points in the window
};

struct CandidateStats {
  int coarse_points = 0;  // finite coarse points within z_max
  int above_plane = 0;    // of those, off the table plane on the camera's side
  bool plane_found = false;
};

/// The table: the largest plane of the frame's coarse view (options' stride, z_max, plane
/// distance), as ProposeCandidates finds it; nullopt when it covers less than
/// min_plane_fraction of the image's pixels (finite or not: a cut-out object's face is no
/// table).
std::optional<Eigen::Vector4f> TablePlane(const Cloud& organized, const CandidateOptions& options);

/// The candidates of an organized frame, best first, at most max_candidates and no two closer
/// than the model's radius. Empty when the cloud is not organized or nothing stands out.
/// Preconditions: options.IsValid(); model.radius_m > 0.
std::vector<Candidate> ProposeCandidates(const Cloud& organized, const CameraIntrinsics& intrinsics,
                                         const ModelSignature& model,
                                         const CandidateOptions& options,
                                         CandidateStats* stats = nullptr);

}  // namespace saccade
