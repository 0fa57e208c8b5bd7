// Captures of one object put into one frame: a model seen from several sides (saccade model
// --captures, and eval's models from other captures). Each pair of captures is aligned by the
// recognizer itself (one capture's object described as a model, found in the other's, verified)
// and refined by ICP on every point; the captures are then chained to a reference along the
// alignments that agree best, and the alignments left out of the chain say how consistent the
// loop is.
#pragma once

#include "core/model.h"
#include "core/parallel.h"
#include "core/recognition_options.h"
#include "core/types.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace saccade {

struct AlignmentOptions {
  RecognitionOptions recognition;  // how one capture is found in the other
  int icp_iterations = 30;
  float icp_max_distance_m = 0.01f;  // pairs farther apart are left out of ICP's steps
  float inlier_distance_m = 0.005f;  // a point within this of the other capture overlaps it
  float min_overlap = 0.3f;          // an alignment overlapping less is not used
  float free_space_m = 0.02f;        // a point this far in front of b's surface is seen through
  float max_seen_through = 0.05f;    // an alignment seeing through more is not used
  float min_colour = 0.0f;           // an alignment whose colours agree less is not used
};

/// How capture `a` lies in capture `b`.
struct ViewAlignment {
  bool found = false;  // recognized and overlapping at least min_overlap
  Eigen::Matrix4f pose = Eigen::Matrix4f::Identity();        // a's points into b's frame
  Eigen::Matrix4f recognized = Eigen::Matrix4f::Identity();  // the same, before ICP
  float overlap = 0;     // share of a's points within inlier_distance_m of b's points
  float rmse_m = 0;      // of those points' distances
  float confidence = 0;  // the recognizer's, before ICP
  /// Share of a's points that b's camera would have seen in front of b's surface (b organized;
  /// 0 otherwise): where b saw through to the object, nothing of a can be.
  float seen_through = 0;
  /// How well the overlapping points' colours agree (chromaticity histograms' intersection, in
  /// [0, 1]); -1 without colour.
  float colour = -1;
};

/// Aligns capture `a` (described) to `b` (its object's points, b's camera frame; organized, the
/// rest NaN, for the free-space check).
ViewAlignment AlignViews(const ModelDescription& a, const Cloud& b,
                         const AlignmentOptions& options);

/// The overlap of `a` moved by `pose` on `b`: the share of a's finite points within
/// `inlier_distance_m` of b's, and their RMS distance.
std::pair<float, float> Overlap(const Cloud& a, const Eigen::Matrix4f& pose, const Cloud& b,
                                float inlier_distance_m);

/// Every ordered pair of `captures` aligned (`pairs[a][b]`: a to b; the diagonal unset), each
/// capture described once; `parallel` runs the describing and the pairs.
std::vector<std::vector<ViewAlignment>> AlignAll(const std::vector<const Cloud*>& captures,
                                                 const AlignmentOptions& options,
                                                 const ParallelFor& parallel = SerialFor);

/// Each capture's pose in `reference`'s frame, chained along a maximum spanning tree of the
/// found alignments (`pairs[a][b]` aligns a to b; either direction serves). An alignment weighs
/// the number of third captures that close a loop with it within 2 cm, then its overlap: a
/// wrong alignment seldom agrees with two others. Only captures with `use[i]` take part (nor
/// do the loops pass through the others). nullopt for a capture no alignment reaches. `parent`,
/// when given, receives each placed capture's predecessor in the chain (-1 for the reference
/// and for captures left out).
std::vector<std::optional<Eigen::Matrix4f>> ChainViews(
    const std::vector<std::vector<ViewAlignment>>& pairs, const std::vector<const Cloud*>& captures,
    const std::vector<bool>& use, std::size_t reference, std::vector<int>* parent = nullptr);

/// The used capture whose alignments weigh most (as ChainViews weighs them): the best
/// connected, which chains the others in the fewest and surest steps.
std::size_t BestReference(const std::vector<std::vector<ViewAlignment>>& pairs,
                          const std::vector<const Cloud*>& captures, const std::vector<bool>& use);

/// The captures placed by `poses` (nullopt: left out) as the views of one model: points moved
/// into the reference frame, each view's sensor origin and orientation set from its pose.
std::vector<Cloud> PlaceViews(const std::vector<const Cloud*>& captures,
                              const std::vector<std::optional<Eigen::Matrix4f>>& poses);

/// How far the found alignments left out of the chain disagree with it: the largest distance,
/// over those alignments, between where the chain and the alignment put a's centroid (metres;
/// 0 when every found alignment is in the chain). A loop that closes agrees.
float LoopDisagreement(const std::vector<std::vector<ViewAlignment>>& pairs,
                       const std::vector<std::optional<Eigen::Matrix4f>>& poses,
                       const std::vector<const Cloud*>& captures);

}  // namespace saccade
