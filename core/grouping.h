// Correspondence grouping: from descriptor matches to pose hypotheses (paper Algorithm 5, and
// the consensus of local frames beside it).
#pragma once

#include "core/features.h"
#include "core/recognition_options.h"
#include "core/types.h"

#include <utility>
#include <vector>

namespace saccade {

/// Groups correspondences by 3D Hough voting of the model centroid (paper Algorithm 5) and
/// estimates each instance's pose from its inlying correspondences (proper rotations only).
/// `correspondences` are (model descriptor index, scene descriptor index). `turns`: the model's
/// symmetries about its centroid (FindSymmetries, identity first; empty or one: none); a peak's
/// matches are fitted as one pose, each through the turn its local frames agree with.
std::vector<Detection> HoughGroup(const Descriptors& model, const Cloud& model_cloud,
                                  const Eigen::Vector3f& model_centroid, const Descriptors& scene,
                                  const Cloud& scene_cloud,
                                  const std::vector<std::pair<int, int>>& correspondences,
                                  const RecognitionOptions& options,
                                  const std::vector<Eigen::Matrix3f>& turns = {});

/// Groups correspondences by consensus on the poses their local frames give (see
/// RecognitionOptions::consensus_grouping); most agreed first. `turns` as HoughGroup's: a match
/// agrees with a pose through any turn of the model.
std::vector<Detection> ConsensusGroup(const Descriptors& model, const Cloud& model_cloud,
                                      const Eigen::Vector3f& model_centroid,
                                      const Descriptors& scene, const Cloud& scene_cloud,
                                      const std::vector<std::pair<int, int>>& correspondences,
                                      const RecognitionOptions& options,
                                      const std::vector<Eigen::Matrix3f>& turns = {});

/// `a` and the hypotheses of `b` whose centroid is at least `min_separation_m` from all of
/// `a`'s, by votes.
std::vector<Detection> MergeHypotheses(std::vector<Detection> a, std::vector<Detection> b,
                                       float min_separation_m);

}  // namespace saccade
