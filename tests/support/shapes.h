// Hand-made clouds for tests of the stages: no real data needed.
#pragma once

#include "core/types.h"

namespace saccade::testing {

// A synthetic "model": points on three faces of a box, with a dent to break symmetry.
inline Cloud BoxCorner() {
  Cloud c;
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 60; ++j) {
      const float a = i * 0.002f, b = j * 0.002f;
      PointT p;
      p.x = a, p.y = b, p.z = (a > 0.05f && b > 0.05f && a < 0.07f && b < 0.08f) ? 0.01f : 0.0f;
      c.push_back(p);
      p.x = a, p.y = 0, p.z = b;
      c.push_back(p);
      p.x = 0, p.y = a, p.z = b;
      c.push_back(p);
    }
  return c;
}

// A flat rectangle of w x h metres sampled every `spacing` metres, with a few NaN points.
inline Cloud Grid(float w, float h, float spacing) {
  Cloud c;
  for (float x = 0; x <= w + 1e-6f; x += spacing)
    for (float y = 0; y <= h + 1e-6f; y += spacing) {
      PointT p;
      p.x = x, p.y = y, p.z = 1;
      c.push_back(p);
    }
  for (std::size_t i = 0; i < c.size(); i += 50) c[i].z = NAN;
  return c;
}

}  // namespace saccade::testing
