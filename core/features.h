// Local geometry of a cloud: radius neighbourhoods (neighbor_search.h), normals (normals.h),
// SHOT local reference frames and descriptors (shot.h), and the camera intrinsics an organized
// cloud implies.
#pragma once

#include "core/neighbor_search.h"
#include "core/normals.h"
#include "core/shot.h"
#include "core/types.h"

#include <optional>

namespace saccade {

/// Estimates pinhole intrinsics from an organized cloud's own points (x = (u - cx) z / fx);
/// nullopt when the cloud is unorganized or has too few finite points.
std::optional<CameraIntrinsics> EstimateIntrinsics(const Cloud& cloud);

}  // namespace saccade
