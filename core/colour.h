// Colour histograms in rg chromaticity, shared by verification (do the seen colours agree?) and
// the whole-frame candidates (where in the frame are the model's colours?).
#pragma once

#include "core/types.h"

#include <algorithm>
#include <array>

namespace saccade {

/// A colour histogram in rg chromaticity (r / (r+g+b), g / (r+g+b)), 8 x 8 bins over [0, 2/3]:
/// brightness is divided out, so another exposure moves nothing.
using ColourHistogram = std::array<float, 64>;

/// The bin of a point's colour, or -1 when it is too dark to carry a chromaticity.
inline int ColourBin(const PointT& p) {
  constexpr float kMinSum = 30;
  const float sum = float(p.r) + float(p.g) + float(p.b);
  if (sum < kMinSum) return -1;
  const int r = std::min(7, int(12 * p.r / sum)), g = std::min(7, int(12 * p.g / sum));
  return g * 8 + r;
}

/// Counts the point's colour; pixels too dark to carry a chromaticity are left out.
inline void AddColour(const PointT& p, ColourHistogram* h) {
  const int bin = ColourBin(p);
  if (bin >= 0) (*h)[bin] += 1;
}

/// Scales the histogram to sum to 1 (an empty one stays empty).
inline void Normalize(ColourHistogram* h) {
  float total = 0;
  for (float v : *h) total += v;
  if (total > 0)
    for (float& v : *h) v /= total;
}

/// The intersection of two normalized histograms, in [0, 1].
inline float Intersection(const ColourHistogram& a, const ColourHistogram& b) {
  float s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += std::min(a[i], b[i]);
  return s;
}

/// True when nine in ten of the cloud's points or more are exact greys (r = g = b): a mesh's
/// material colours. They say nothing of the chromaticity a camera will see of the object (its
/// white balance, its print), so such a model is looked for and verified on geometry alone.
inline bool MaterialGreys(const Cloud& cloud) {
  std::size_t grey = 0;
  for (const PointT& p : cloud.points) grey += p.r == p.g && p.g == p.b;
  return !cloud.empty() && grey * 10 >= cloud.size() * 9;
}

}  // namespace saccade
