// The turns that map a model onto itself (a cube's 24, a box's 4, a can's many): a symmetric
// model's correct matches spread over as many poses as it has turns, so grouping must count
// them as one.
#pragma once

#include "core/shot.h"
#include "core/types.h"

#include <Eigen/Core>

#include <vector>

namespace saccade {

struct SymmetryOptions {
  float tolerance_m = 0.004f;      // a turned point lies this near the surface
  float min_share = 0.9f;          // ...for at least this share of the points
  float max_sqr_distance = 0.25f;  // keypoints whose descriptors are this near propose a turn
  int max_turns = 48;              // found at most (the identity included)
};

/// The rotations about `centre` that map `surface` onto itself, identity first. Candidates come
/// from keypoints alike (near descriptors, as far from the centre): the turn their local frames
/// give; each is refined by aligning turned points with the surface (about the centre, no
/// translation) and kept when at least min_share of the points land within tolerance_m. Turns
/// within 10 degrees of one kept are one. Deterministic (no random draw).
std::vector<Eigen::Matrix3f> FindSymmetries(const Cloud& surface, const Eigen::Vector3f& centre,
                                            const Descriptors& descriptors,
                                            const SymmetryOptions& options);

/// The angle of rotation `r`, radians.
float RotationAngle(const Eigen::Matrix3f& r);

}  // namespace saccade
