// Radius neighbourhoods over a cloud: by pixel window on an organized cloud, by kd-tree on any.
#pragma once

#include "core/camera.h"
#include "core/types.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace saccade {

/// Radius neighbourhoods over a search surface. Indices are into the cloud the search was made
/// for. Thread-safe for concurrent queries once constructed.
class NeighborSearch {
 public:
  virtual ~NeighborSearch() = default;
  /// Appends the surface points within `radius_m` of surface point `query` (itself included
  /// unless the window is sampled), with their squared distances. Clears both outputs first.
  virtual void Radius(int query, float radius_m, std::vector<int>* indices,
                      std::vector<float>* sqr_dists) const = 0;
};

/// Search on an organized (image-shaped) cloud: scans the pixel window that a sphere of the
/// radius covers at the query's depth. Only points with mask[i] != 0 are surface points; the
/// mask (size = cloud size) and cloud must outlive the search. A window reaching farther than
/// `max_half_window_px` from the query is sampled every few pixels, so that a wide support near
/// the camera holds about as many points as one of that half-width (0: every pixel).
std::unique_ptr<NeighborSearch> MakeOrganizedSearch(const Cloud& cloud,
                                                    const CameraIntrinsics& intrinsics,
                                                    const std::vector<std::uint8_t>& mask,
                                                    int max_half_window_px = 0);

/// Search over the masked points of any cloud with a kd-tree (built here, once).
std::unique_ptr<NeighborSearch> MakeKdTreeSearch(const Cloud& cloud,
                                                 const std::vector<std::uint8_t>& mask);

}  // namespace saccade
