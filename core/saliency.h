// Where to look when the target is lost for good: the salient regions of a coarse view of the
// frame, for the attention loop's saccade fallback (paper §3.4 leaves saliency open).
#pragma once

#include "core/schema.h"
#include "core/types.h"

#include <string>
#include <vector>

namespace saccade {

struct SaliencyOptions {
  int stride_px = 8;          // the coarse view: every stride-th pixel of every stride-th row
  float edge_jump_m = 0.03f;  // a depth step larger than this across a sample makes it an edge
  float cell_m = 0.25f;       // regions are cubic cells of this edge (about the fovea's box)
  int max_regions = 16;

  bool IsValid(std::string* error) const;
  bool operator==(const SaliencyOptions& o) const { return SameFields(*this, o); }
  /// The keys of the `saliency` section (core/schema.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("stride_px", &stride_px);
    a->Visit("edge_jump_m", &edge_jump_m);
    a->Visit("cell_m", &cell_m);
    a->Visit("max_regions", &max_regions);
  }
};

/// Salient regions of an organized cloud (camera frame, metres), most salient first. A sample
/// is salient when it is the near side of a depth edge: an object standing out from what lies
/// behind it, where a wall or a table top has none. A region is the centroid of the salient
/// samples of one cell, ranked by their count. Empty when the cloud is not organized.
std::vector<Eigen::Vector3f> SalientRegions(const Cloud& organized, const SaliencyOptions& options);

}  // namespace saccade
