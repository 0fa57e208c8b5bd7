// A FLANN result set of one: the nearest point within a bound. Starting at the bound lets a
// search prune every branch farther away from its first step (FLANN's own sets start at
// infinity). Used with FLANN's indices directly: their generic knnSearch wrappers cost more
// per single query (matrix conversions, an OpenMP region) than a small search does.
#pragma once

#include <flann/util/result_set.h>

#include <cmath>
#include <cstddef>
#include <limits>

namespace saccade {

class NearestWithin final : public flann::ResultSet<float> {
 public:
  /// A point at exactly sqrt(max_sqr_distance) counts.
  explicit NearestWithin(float max_sqr_distance)
      : sqr_distance_(std::nextafter(max_sqr_distance, std::numeric_limits<float>::infinity())) {}

  bool full() const override { return true; }
  void addPoint(float sqr_distance, std::size_t index) override {
    if (sqr_distance < sqr_distance_) sqr_distance_ = sqr_distance, index_ = int(index);
  }
  float worstDist() const override { return sqr_distance_; }

  /// The nearest point's index, or -1 when none lies within the bound.
  int index() const { return index_; }
  /// Its squared distance (meaningless when index() is -1).
  float sqr_distance() const { return sqr_distance_; }

 private:
  float sqr_distance_;
  int index_ = -1;
};

}  // namespace saccade
